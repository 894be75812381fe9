// The simulated camera: geometry, each ToF effect on and off, determinism,
// the noise model's statistics, ground truth.
#include <cmath>
#include <cstdlib>
#include <string>
#include <vector>

#include "cmocka_cpp.hpp"
#include "sim_hal/ground_truth.hpp"
#include "sim_hal/scenario.hpp"
#include "sim_hal/sim_random.hpp"
#include "sim_hal/tof_sensor.hpp"

using namespace sim_hal;

namespace {

ToFSettings all_off() {
  ToFSettings s;
  s.noise = s.flying_pixels = s.flying_filter = s.invalid_pixels = s.multipath = false;
  return s;
}

// A wall facing the camera (camera at the origin looking along world -x).
Scene wall_scene(double distance_m, double tilt_deg = 0.0) {
  Scene scene;
  const double t = tilt_deg * M_PI / 180.0;
  scene.add_wall(Eigen::Vector3d(-distance_m, 0, 0), Eigen::Vector3d(std::cos(t), std::sin(t), 0),
                 Eigen::Vector3d(0, 0, 1), 20.0, 20.0);
  return scene;
}

// The wall of wall_scene(0.6) with a handrail on it, centred on the view.
Scene wall_with_handrail(HandrailKind kind, const Eigen::Vector3d& axis, double length_m) {
  Scene scene = wall_scene(0.6);
  Handrail h;
  h.kind = kind;
  h.foot_center = Eigen::Vector3d(-0.6, 0, 0);
  h.normal = Eigen::Vector3d(1, 0, 0);
  h.axis = axis;
  h.bar_length_m = length_m;
  scene.add_handrail(h);
  return scene;
}

Eigen::Isometry3d looking_at_wall() {
  return camera_pose(Eigen::Vector3d::Zero(), Eigen::Vector3d(-1, 0, 0), Eigen::Vector3d(0, 0, 1),
                     Eigen::Vector3d::Zero());
}

// The renderer casts rays through each surface's local frame in single
// precision, over per-tile lists; intersect_scene is the double-precision
// reference over every surface. Every pixel of shipped scenes (walls,
// boxes, cables, both analytic handrails, a mesh handrail, a corner, rack
// walls with their tracks, gaps and bays, the module rail, the Columbus
// module's mesh seen from inside) at several poses: the same surface, the
// same range within 20 um (where the sensor keeps the pixel; the hit within
// 20 um of the surface everywhere). A ray
// grazing a silhouette may fall either side of it in float: at most 0.05 %
// of the pixels may disagree on which surface they hit.
void test_fast_ray_casting_matches_the_reference(void**) {
  const char* root = std::getenv("HRP_SOURCE_DIR");
  const std::string folder = std::string(root ? root : ".") + "/sim_hal/scenarios/";
  const CameraIntrinsics cam = pico_flexx_intrinsics();
  const std::vector<Eigen::Vector3f> rays = pixel_rays(cam);
  int compared = 0, hits = 0, disagree = 0;
  double worst_m = 0.0, worst_normal_m = 0.0;
  for (const char* name :
       {"table2-iss.json", "table2-round.json", "table2-iss-mesh.json", "corner.json",
        "two-perpendicular.json", "approach-round.json", "rack-table2-iss-mesh-21-5.json",
        "rack-no-handrail-corner.json", "rack-clutter-horizontal-21-5.json",
        "rack-approach-overhead-module-rail.json", "columbus-approaches.json"}) {
    Scenario sc;
    std::string error;
    if (!load_scenario(folder + name, &sc, &error)) print_error("%s\n", error.c_str());
    assert_true(error.empty());
    DepthRenderer r(cam, all_off());
    std::vector<hal::DepthPoint> pts;
    for (std::size_t f = 0; f < sc.T_world_cam.size(); f += sc.T_world_cam.size() / 4 + 1) {
      const Eigen::Isometry3d& T = sc.T_world_cam[f];
      r.render(sc.scene, T, sc.seed, f, &pts);
      for (std::size_t i = 0; i < rays.size(); ++i) {
        const Eigen::Vector3d ray_world = T.rotation() * rays[i].cast<double>();
        Hit hit;
        const bool want = intersect_scene(sc.scene, T.translation(), ray_world, 1e-4,
                                          sc.sensor.range_max_m * 1.5, &hit);
        const std::int32_t got_surface = r.hit_surface()[i];
        ++compared;
        if ((want ? hit.surface : -1) != got_surface) {
          ++disagree;
          continue;
        }
        if (!want) continue;
        ++hits;
        // Along a ray grazing a plane, float's error in where the plane is
        // grows as 1 / cos(incidence) (a rack face's side seen edge-on,
        // cos 0.002): the hit must lie within 20 um of the surface, and its
        // range within 20 um where the sensor keeps the pixel (cos >= 0.12).
        const double error_m = std::fabs(hit.t - r.true_range_m()[i]);
        const double cos_incidence = std::fabs(hit.normal.dot(ray_world));
        worst_normal_m = std::max(worst_normal_m, error_m * cos_incidence);
        if (cos_incidence >= 0.12) worst_m = std::max(worst_m, error_m);
      }
    }
  }
  print_message(
      "%d pixels, %d hits, %d disagree on the surface, worst range %.2f um (kept pixels), worst "
      "distance from the surface %.2f um\n",
      compared, hits, disagree, worst_m * 1e6, worst_normal_m * 1e6);
  assert_true(hits > compared / 2);
  assert_true(disagree * 2000 <= compared);
  assert_true(worst_m < 20e-6);
  assert_true(worst_normal_m < 20e-6);
}

// The ziggurat behind every noise draw: a million draws have the standard
// normal's mean, variance and kurtosis, and its share beyond 3 sigma and
// beyond the base layer's edge (3.44 sigma, where draws come from the tail
// routine rather than the layers).
void test_normal_draws_are_standard_normal(void**) {
  SimRandom rng(2026);
  const int n = 1000000;
  double s1 = 0.0, s2 = 0.0, s4 = 0.0;
  int beyond_3 = 0, in_tail = 0;
  for (int k = 0; k < n; ++k) {
    const double x = rng.normal();
    s1 += x;
    s2 += x * x;
    s4 += x * x * x * x;
    beyond_3 += std::fabs(x) > 3.0;
    in_tail += std::fabs(x) > 3.442619855899;
  }
  const double mean = s1 / n, variance = s2 / n, kurtosis = s4 / n;
  print_message("mean %.4f variance %.4f kurtosis %.3f beyond 3 sigma %.5f tail %.6f\n", mean,
                variance, kurtosis, static_cast<double>(beyond_3) / n,
                static_cast<double>(in_tail) / n);
  assert_true(std::fabs(mean) < 0.005);
  assert_true(std::fabs(variance - 1.0) < 0.005);
  assert_true(std::fabs(kurtosis - 3.0) < 0.05);
  assert_true(std::fabs(static_cast<double>(beyond_3) / n - 0.0027) < 0.0003);
  assert_true(std::fabs(static_cast<double>(in_tail) / n - 0.000576) < 0.00012);
}

void test_plane_geometry(void**) {
  const CameraIntrinsics cam = pico_flexx_intrinsics();
  for (double tilt : {0.0, 35.0}) {
    DepthRenderer r(cam, all_off());
    std::vector<hal::DepthPoint> pts;
    r.render(wall_scene(0.8, tilt), looking_at_wall(), 1, 0, &pts);
    // World normal (cos t, sin t, 0) seen from the camera (x = world y,
    // z = world -x); the wall passes through world (-0.8, 0, 0).
    const double t = tilt * M_PI / 180.0;
    const Eigen::Vector3d n_cam(std::sin(t), 0.0, -std::cos(t));
    int checked = 0;
    for (const hal::DepthPoint& p : pts) {
      if (!hal::is_valid(p)) continue;
      assert_near(n_cam.dot(Eigen::Vector3d(p.x_m, p.y_m, p.z_m)), -0.8 * std::cos(t), 1e-4);
      ++checked;
    }
    assert_int_equal(checked, 224 * 171);
  }
  // Straight ahead, z is the distance.
  DepthRenderer r(cam, all_off());
  std::vector<hal::DepthPoint> pts;
  r.render(wall_scene(1.25), looking_at_wall(), 1, 0, &pts);
  const int centre = static_cast<int>(std::lround(cam.lens.cy_px)) * 224 +
                     static_cast<int>(std::lround(cam.lens.cx_px));
  assert_near(pts[centre].z_m, 1.25, 1e-5);
}

void test_field_of_view(void**) {
  // The corners' rays span about 62 x 45 degrees through the edge centres.
  const CameraIntrinsics cam = pico_flexx_intrinsics();
  const std::vector<Eigen::Vector3f> rays = pixel_rays(cam);
  const int mid_row = static_cast<int>(std::lround(cam.lens.cy_px));
  const int mid_col = static_cast<int>(std::lround(cam.lens.cx_px));
  const double h = std::atan2(rays[mid_row * 224 + 223].x(), rays[mid_row * 224 + 223].z()) -
                   std::atan2(rays[mid_row * 224].x(), rays[mid_row * 224].z());
  const double v = std::atan2(rays[170 * 224 + mid_col].y(), rays[170 * 224 + mid_col].z()) -
                   std::atan2(rays[mid_col].y(), rays[mid_col].z());
  assert_near(h * 180.0 / M_PI, 62.0, 1.5);
  assert_near(v * 180.0 / M_PI, 45.0, 2.0);
  // Projection inverts the rays.
  Eigen::Vector2d px;
  assert_true(project(cam, rays[50 * 224 + 30].cast<double>(), &px));
  assert_near(px.x(), 30.0, 1e-3);
  assert_near(px.y(), 50.0, 1e-3);
  // The corners' rays, the farthest off axis, are within the lens model
  // and project back onto their pixels.
  for (int row : {0, 170}) {
    for (int col : {0, 223}) {
      const Eigen::Vector3d ray = rays[row * 224 + col].cast<double>();
      assert_true(project(cam, ray, &px));
      assert_near(px.x(), col, 1e-3);
      assert_near(px.y(), row, 1e-3);
    }
  }
  // A point 65 deg off axis, far outside the 62 deg field: the distortion
  // polynomial alone would fold it back to about pixel (223, 54).
  const Eigen::Vector3d far_out(2.14, -0.61, 1.0);
  const Eigen::Vector2d folded = distort(cam.lens, Eigen::Vector2d(2.14, -0.61));
  assert_true(cam.lens.cx_px + cam.lens.fx_px * folded.x() < 224.0);
  assert_false(project(cam, far_out, &px));
  assert_false(within_lens_model(cam.lens, Eigen::Vector2d(2.14, -0.61)));
}

void test_bar_image_width(void**) {
  const CameraIntrinsics cam = pico_flexx_intrinsics();
  const Scene scene = wall_with_handrail(HandrailKind::kPaperRound, Eigen::Vector3d(0, 0, 1), 0.55);
  DepthRenderer r(cam, all_off());
  std::vector<hal::DepthPoint> pts;
  r.render(scene, looking_at_wall(), 1, 0, &pts);
  const int row = static_cast<int>(std::lround(cam.lens.cy_px));
  int width = 0;
  for (int c = 0; c < 224; ++c) width += pts[row * 224 + c].z_m < 0.59f;
  const double range = 0.6 - 0.0825;
  assert_near(width, cam.lens.fx_px * 0.035 / range, 1.5);
}

Scene bar_on_wall(HandrailKind kind) {
  return wall_with_handrail(kind, Eigen::Vector3d(0, 0, 1), 0.3);
}

struct EffectCounts {
  int invalid = 0, off_surface = 0, deviating = 0;
};

// Counts what an effect did, against the exact ranges of the same frame.
EffectCounts count_effects(const ToFSettings& s, const Scene& scene) {
  DepthRenderer r(pico_flexx_intrinsics(), s);
  std::vector<hal::DepthPoint> pts;
  r.render(scene, looking_at_wall(), 3, 0, &pts);
  EffectCounts c;
  for (std::size_t i = 0; i < pts.size(); ++i) {
    if (!hal::is_valid(pts[i])) {
      ++c.invalid;
      continue;
    }
    const double range =
        std::sqrt(pts[i].x_m * pts[i].x_m + pts[i].y_m * pts[i].y_m + pts[i].z_m * pts[i].z_m);
    const double err = range - r.true_range_m()[i];
    c.deviating += std::fabs(err) > 1e-5;
    c.off_surface += std::fabs(err) > 0.01;  // mixed depths, centimetres off
  }
  return c;
}

void test_each_effect_switches(void**) {
  const Scene scene = bar_on_wall(HandrailKind::kIss);
  const EffectCounts none = count_effects(all_off(), scene);
  assert_int_equal(none.invalid, 0);
  assert_int_equal(none.deviating, 0);

  ToFSettings noise = all_off();
  noise.noise = true;
  assert_true(count_effects(noise, scene).deviating > 30000);

  ToFSettings flying = all_off();
  flying.flying_pixels = true;
  const EffectCounts fly = count_effects(flying, scene);
  assert_true(fly.off_surface > 20);  // mixed pixels at the bar's edges
  flying.flying_filter = true;
  assert_true(count_effects(flying, scene).invalid > 20);  // the vendor filter drops some

  ToFSettings multipath = all_off();
  multipath.multipath = true;
  const EffectCounts mp = count_effects(multipath, scene);
  assert_true(mp.deviating > 100);      // the wall around the bar reads long
  assert_int_equal(mp.off_surface, 0);  // by millimetres, not centimetres

  // Invalid pixels: grazing incidence and out of range.
  ToFSettings invalid = all_off();
  invalid.invalid_pixels = true;
  // (Rays that pass the grazing wall's far edge hit nothing either way.)
  assert_true(count_effects(invalid, wall_scene(0.8, 86.0)).invalid >
              count_effects(all_off(), wall_scene(0.8, 86.0)).invalid + 5000);
  assert_int_equal(count_effects(invalid, wall_scene(5.0)).invalid, 224 * 171);
}

void test_same_seed_same_bytes(void**) {
  const Scene scene = bar_on_wall(HandrailKind::kPaperRound);
  DepthRenderer a(pico_flexx_intrinsics(), ToFSettings{}),
      b(pico_flexx_intrinsics(), ToFSettings{});
  std::vector<hal::DepthPoint> pa, pb, pc;
  a.render(scene, looking_at_wall(), 99, 4, &pa);
  b.render(scene, looking_at_wall(), 99, 4, &pb);
  a.render(scene, looking_at_wall(), 100, 4, &pc);
  assert_memory_equal(pa.data(), pb.data(), pa.size() * sizeof(hal::DepthPoint));
  assert_true(std::memcmp(pa.data(), pc.data(), pa.size() * sizeof(hal::DepthPoint)) != 0);
}

void test_noise_matches_its_model(void**) {
  // 10,000 pixels of a wall at 1 m: the measured spread of (measured -
  // exact) / reported sigma must be 1 within 10 %.
  ToFSettings s = all_off();
  s.noise = true;
  DepthRenderer r(pico_flexx_intrinsics(), s);
  std::vector<hal::DepthPoint> pts;
  r.render(wall_scene(1.0), looking_at_wall(), 5, 0, &pts);
  double sum = 0.0, sum2 = 0.0;
  int n = 0;
  for (int row = 35; row < 135 && n < 10000; ++row) {
    for (int col = 62; col < 162 && n < 10000; ++col) {
      const std::size_t i = static_cast<std::size_t>(row * 224 + col);
      const hal::DepthPoint& p = pts[i];
      const double range = std::sqrt(p.x_m * p.x_m + p.y_m * p.y_m + p.z_m * p.z_m);
      const double z = (range - r.true_range_m()[i]) / p.noise_m;
      sum += z;
      sum2 += z * z;
      ++n;
    }
  }
  assert_int_equal(n, 10000);
  const double mean = sum / n, sd = std::sqrt(sum2 / n - mean * mean);
  assert_near(sd, 1.0, 0.1);
  assert_near(mean, 0.0, 0.05);
}

void test_ground_truth(void**) {
  const CameraIntrinsics cam = pico_flexx_intrinsics();
  // Horizontal in the image.
  const Scene scene = wall_with_handrail(HandrailKind::kIss, Eigen::Vector3d(0, 1, 0), 0.55);
  const FrameTruth t = compute_truth(scene, cam, looking_at_wall(), 3);
  assert_int_equal(t.handrails.size(), 1);
  const HandrailTruth& ht = t.handrails[0];
  assert_near(ht.visible_fraction, 1.0, 1e-9);
  assert_true(ht.end_in_view[0] && ht.end_in_view[1]);
  assert_near(ht.center_cam.z(), 0.6 - 0.061, 1e-9);
  assert_near(ht.normal_cam.z(), -1.0, 1e-9);
  assert_near((ht.ends_cam[1] - ht.ends_cam[0]).norm(), 0.55, 1e-9);
  // Turned away: nothing in view.
  const Eigen::Isometry3d away = camera_pose(Eigen::Vector3d::Zero(), Eigen::Vector3d(1, 0, 0),
                                             Eigen::Vector3d(0, 0, 1), Eigen::Vector3d::Zero());
  assert_int_equal(compute_truth(scene, cam, away, 4).handrails.size(), 0);
  assert_true(truth_to_json(t, "f.pcd").find("\"end_in_view\":[true,true]") != std::string::npos);
}

}  // namespace

int main() {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_plane_geometry),
      cmocka_unit_test(test_field_of_view),
      cmocka_unit_test(test_bar_image_width),
      cmocka_unit_test(test_each_effect_switches),
      cmocka_unit_test(test_same_seed_same_bytes),
      cmocka_unit_test(test_noise_matches_its_model),
      cmocka_unit_test(test_ground_truth),
      cmocka_unit_test(test_fast_ray_casting_matches_the_reference),
      cmocka_unit_test(test_normal_draws_are_standard_normal),
  };
  return cmocka_run_group_tests(tests, nullptr, nullptr);
}
