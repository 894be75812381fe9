// Plane estimation (the paper's first step) on analytic scenes: flat walls
// at any tilt, rack faces at different depths, a face holding a quarter of
// the view, no plane at all.
#include <Eigen/Geometry>
#include <cmath>
#include <vector>

#include "cmocka_cpp.hpp"
#include "estimator/plane_estimation.hpp"
#include "synthetic_cloud.hpp"

using namespace estimator;
using testing_support::SyntheticScene;

namespace {

constexpr double kWall = 0.6;

DetectorConfig test_config() {
  DetectorConfig cfg;
  cfg.handrail = paper_round_handrail(0.3f);
  cfg.max_width = 160;
  cfg.max_height = 120;
  return cfg;
}

// A wall tilted about the image's y axis, d_m away along its normal, under
// 2 mm of noise.
SyntheticScene tilted_wall(double tilt_deg, double d_m) {
  SyntheticScene s;
  const double t = tilt_deg * M_PI / 180.0;
  s.nx = -std::sin(t);
  s.nz = -std::cos(t);
  s.d = d_m;
  s.noise_m = 0.002;
  return s;
}

// A rendered pixel moved along its ray by `scale` (a face nearer or
// farther), its noise scaled with it.
void move_along_ray(CloudPoint& p, double scale) {
  p.x_m *= static_cast<float>(scale);
  p.y_m *= static_cast<float>(scale);
  p.z_m *= static_cast<float>(scale);
}

void test_plane_fronto_parallel_and_tilted(void**) {
  const DetectorConfig cfg = test_config();
  for (double tilt_deg : {0.0, 30.0, 50.0}) {
    SyntheticScene s;
    const double t = tilt_deg * M_PI / 180.0;
    s.nx = -std::sin(t);
    s.nz = -std::cos(t);
    s.noise_m = 0.002;
    std::vector<CloudPoint> pts;
    const OrganizedCloud cloud = testing_support::render(s, &pts);
    Workspace ws(cloud.size());
    sample_valid_points(cloud, cfg, ws);
    Random rng(3);
    const PlaneEstimate p = estimate_plane(cloud, cfg, rng, ws);
    assert_true(p.found);
    // Normal toward the camera, distance right to a millimetre.
    assert_near(p.plane.normal.x(), s.nx, 0.01);
    assert_near(p.plane.normal.z(), s.nz, 0.01);
    assert_near(p.plane.d, kWall, 0.001);
    assert_true(p.inliers > cloud.size() * 9 / 10);
  }
}

// A deck view of a rack wall (as in rack-approach-deck-41-5): a face, one
// a centimetre behind it, a 12 cm recess and a face 5.8 cm behind, each a
// strip of the image, all parallel to the image plane. A plane tilted
// across them holds strips of several within the inlier band and outscores
// any one face; the fit must come out parallel to the faces, on one.
void test_plane_across_rack_faces_is_not_tilted(void**) {
  DetectorConfig cfg = test_config();
  SyntheticScene s;
  s.d = 0.50;
  s.noise_m = 0.0035;
  std::vector<CloudPoint> pts;
  OrganizedCloud cloud = testing_support::render(s, &pts);
  const double faces_z[] = {0.50, 0.51, 0.62, 0.558};
  const double edges[] = {0.31, 0.48, 0.56, 1.01};  // right edge of each strip, x width
  for (std::uint32_t v = 0; v < cloud.height; ++v) {
    for (std::uint32_t u = 0; u < cloud.width; ++u) {
      CloudPoint& p = pts[v * cloud.width + u];
      int k = 0;
      while (static_cast<double>(u) >= edges[k] * cloud.width) ++k;
      move_along_ray(p, faces_z[k] / s.d);
    }
  }
  Workspace ws(cloud.size());
  sample_valid_points(cloud, cfg, ws);
  // The same with the faces' normal (plane_faces_normal) on.
  for (int run = 0; run < 10; ++run) {
    cfg.plane_faces_normal = run >= 5;
    Random rng(static_cast<std::uint64_t>(run % 5 + 1));
    const PlaneEstimate p = estimate_plane(cloud, cfg, rng, ws);
    assert_true(p.found);
    const float angle_deg =
        std::acos(std::fmin(1.0f, -p.plane.normal.z())) * static_cast<float>(180.0 / M_PI);
    // Without the sharpness search: 8 deg, between the faces. The two
    // faces a centimetre apart, under 3.5 mm of noise, blur into one
    // within a degree.
    assert_true(angle_deg < 1.5f);
    bool on_a_face = false;
    for (double z : faces_z) on_a_face |= std::fabs(p.plane.d - z) < 0.006;
    assert_true(on_a_face);
  }
}

// Two parallel faces 1.2 cm apart, one on each side of a view tilted 10 deg
// across them, under 2 mm of noise (a rail's face beside its neighbour at
// 0.4 m, as in rack-approach-vertical-21-5). The refits of the broad plane
// settle about 2 deg tilted between the two, which puts a bar's front on
// the far side of the view millimetres off its height; with
// plane_faces_normal, cells of the view on one face and a fit over each
// face about its own centroid give their normal.
void test_plane_on_faces_a_centimetre_apart_is_not_tilted(void**) {
  DetectorConfig cfg = test_config();
  cfg.plane_faces_normal = true;
  const SyntheticScene s = tilted_wall(10.0, 0.40);
  std::vector<CloudPoint> pts;
  OrganizedCloud cloud = testing_support::render(s, &pts);
  constexpr double kStep_m = 0.012;
  for (std::uint32_t v = 0; v < cloud.height; ++v) {
    for (std::uint32_t u = cloud.width * 45 / 100; u < cloud.width; ++u) {
      // Onto the face behind.
      move_along_ray(pts[v * cloud.width + u], (s.d + kStep_m) / s.d);
    }
  }
  Workspace ws(cloud.size());
  sample_valid_points(cloud, cfg, ws);
  for (std::uint64_t seed : {1u, 2u, 3u}) {
    Random rng(seed);
    const PlaneEstimate p = estimate_plane(cloud, cfg, rng, ws);
    assert_true(p.found);
    const float cos_true = static_cast<float>(s.nx) * p.plane.normal.x() +
                           static_cast<float>(s.nz) * p.plane.normal.z();
    const float angle_deg = std::acos(std::fmin(1.0f, cos_true)) * static_cast<float>(180.0 / M_PI);
    print_message("seed %d: %.2f deg off, d %.4f m\n", static_cast<int>(seed), angle_deg,
                  p.plane.d);
    assert_true(angle_deg < 0.4f);
    // Without it the broad fit stands, tilted between the faces.
    DetectorConfig broad_only = test_config();
    broad_only.plane_faces_normal = false;
    Random again(seed);
    const PlaneEstimate broad = estimate_plane(cloud, broad_only, again, ws);
    assert_true(broad.found);
    const float broad_cos = static_cast<float>(s.nx) * broad.plane.normal.x() +
                            static_cast<float>(s.nz) * broad.plane.normal.z();
    assert_true(std::acos(std::fmin(1.0f, broad_cos)) * static_cast<float>(180.0 / M_PI) > 1.0f);
    const bool on_a_face =
        std::fabs(p.plane.d - s.d) < 0.003 || std::fabs(p.plane.d - s.d - kStep_m) < 0.003;
    assert_true(on_a_face);
  }
}

// One face with a strip 6 mm proud across a fifth of the view (a flat wall
// with cables lying on it), tilted 20 deg: the faces found along the cells'
// normal lie under a centimetre apart, less than any step between rack
// faces, so plane_faces_normal leaves the broad fit exactly as it was (the
// flat walls are judged as before).
void test_plane_on_one_face_keeps_the_broad_fit(void**) {
  const SyntheticScene s = tilted_wall(20.0, 0.6);
  std::vector<CloudPoint> pts;
  OrganizedCloud cloud = testing_support::render(s, &pts);
  for (std::uint32_t v = cloud.height * 2 / 5; v < cloud.height * 3 / 5; ++v) {
    for (std::uint32_t u = 0; u < cloud.width; ++u) {
      move_along_ray(pts[v * cloud.width + u], (s.d - 0.006) / s.d);
    }
  }
  DetectorConfig faces = test_config(), broad_only = test_config();
  faces.plane_faces_normal = true;
  broad_only.plane_faces_normal = false;
  Workspace ws(cloud.size());
  sample_valid_points(cloud, faces, ws);
  for (std::uint64_t seed : {1u, 2u, 3u}) {
    Random a(seed), b(seed);
    const PlaneEstimate with = estimate_plane(cloud, faces, a, ws);
    const PlaneEstimate without = estimate_plane(cloud, broad_only, b, ws);
    assert_true(with.found && without.found);
    assert_true(with.plane.normal == without.plane.normal);
    assert_float_equal(with.plane.d, without.plane.d, 0.0f);
  }
}

// A face holding only a quarter of the view (24 % of the columns) and
// clutter scattered in depth over the rest, as a rack wall seen with its
// faces, gaps and instruments: no other plane has the 20 % a wall needs.
// One triple in 72 lies on the face, so 40 draws miss it more often than
// not (NO_PLANE); drawing on until an all-inlier triple is 99 % likely
// finds it.
void test_plane_on_a_face_holding_a_quarter_of_the_view(void**) {
  SyntheticScene s;
  s.d = 0.60;
  s.noise_m = 0.002;
  std::vector<CloudPoint> pts;
  OrganizedCloud cloud = testing_support::render(s, &pts);
  for (std::uint32_t v = 0; v < cloud.height; ++v) {
    for (std::uint32_t u = 0; u < cloud.width; ++u) {
      if (u < cloud.width * 24 / 100) continue;
      const std::size_t i = v * cloud.width + u;
      const float z = 0.3f + 0.9f * static_cast<float>((i * 7919) % 1000) / 1000.0f;
      const float k = z / pts[i].z_m;
      pts[i].x_m *= k;
      pts[i].y_m *= k;
      pts[i].z_m = z;
    }
  }
  DetectorConfig adaptive = test_config(), fixed = test_config();
  fixed.plane_max_iterations = fixed.plane_iterations;  // 40 draws, as before
  Workspace ws(cloud.size());
  sample_valid_points(cloud, adaptive, ws);
  auto found_on_the_face = [&](const DetectorConfig& cfg) {
    int n = 0;
    for (std::uint64_t seed = 1; seed <= 40; ++seed) {
      Random rng(seed);
      const PlaneEstimate p = estimate_plane(cloud, cfg, rng, ws);
      n += p.found && std::fabs(p.plane.d - 0.60) < 0.006 && -p.plane.normal.z() > 0.9997f;
    }
    return n;
  };
  const int with_adaptive = found_on_the_face(adaptive);
  const int with_fixed = found_on_the_face(fixed);
  print_message("the face found in %d of 40 runs (40 draws: %d)\n", with_adaptive, with_fixed);
  assert_true(with_adaptive >= 36);  // 98 % expected
  assert_true(with_fixed <= 30);     // 43 % expected (24 of 40 here)
}

void test_plane_fails_without_support(void**) {
  // Points scattered in depth: no plane has 20 % support.
  SyntheticScene s;
  std::vector<CloudPoint> pts;
  testing_support::render(s, &pts);
  for (std::size_t i = 0; i < pts.size(); ++i) {
    const float z = 0.3f + 0.9f * static_cast<float>((i * 7919) % 1000) / 1000.0f;
    const float k = z / pts[i].z_m;
    pts[i].x_m *= k;
    pts[i].y_m *= k;
    pts[i].z_m = z;
  }
  OrganizedCloud cloud{0, 0, 160, 120, pts.data()};
  Workspace ws(cloud.size());
  sample_valid_points(cloud, test_config(), ws);
  Random rng(3);
  assert_false(estimate_plane(cloud, test_config(), rng, ws).found);
}

void test_fit_plane_orients_toward_camera(void**) {
  const CloudPoint pts[3] = {{0, 0, 1, 0, 0, 255}, {1, 0, 1, 0, 0, 255}, {0, 1, 1, 0, 0, 255}};
  const OrganizedCloud cloud{0, 0, 3, 1, pts};
  const std::int32_t idx[3] = {0, 1, 2};
  Plane plane;
  assert_true(fit_plane_least_squares(cloud, idx, 3, &plane));
  assert_near(plane.normal.z(), -1.0, 1e-6);
  assert_near(plane.d, 1.0, 1e-6);
  assert_true(plane.signed_distance(Eigen::Vector3f(0, 0, 0.5f)) > 0.0f);
  assert_false(fit_plane_least_squares(cloud, idx, 2, &plane));
}

}  // namespace

int main() {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_plane_fronto_parallel_and_tilted),
      cmocka_unit_test(test_plane_across_rack_faces_is_not_tilted),
      cmocka_unit_test(test_plane_on_faces_a_centimetre_apart_is_not_tilted),
      cmocka_unit_test(test_plane_on_one_face_keeps_the_broad_fit),
      cmocka_unit_test(test_plane_on_a_face_holding_a_quarter_of_the_view),
      cmocka_unit_test(test_plane_fails_without_support),
      cmocka_unit_test(test_fit_plane_orients_toward_camera),
  };
  return cmocka_run_group_tests(tests, nullptr, nullptr);
}
