// ISS rack walls, the module rail and module meshes in the simulator: real
// renders of a rack wall (faces at their depths, a seat track 1.3 cm proud,
// a gap that returns nothing, a gap and a bay with backs), the ground truth
// of handrails standing on seat tracks, every handrail kind and length, the
// Columbus module's mesh, and that every shipped handrail's feet touch a
// surface.
#include <dirent.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "cmocka_cpp.hpp"
#include "sim_hal/ground_truth.hpp"
#include "sim_hal/scenario.hpp"
#include "sim_hal/tof_sensor.hpp"

using namespace sim_hal;

namespace {

std::string source_dir() {
  const char* root = std::getenv("HRP_SOURCE_DIR");
  return root ? root : ".";
}

ToFSettings all_off() {
  ToFSettings s;
  s.noise = s.flying_pixels = s.flying_filter = s.invalid_pixels = s.multipath = false;
  return s;
}

// A rack wall in the plane x = 0 facing +x (u = world y, v = world z):
// face A (depth 0) with a seat track along its top edge at v = 0.03 and a
// light on it; above it an opening that returns nothing, then face B 3 cm
// back and face C 2 cm proud with a 12 cm deep gap between them; left of
// face A an empty bay 35 cm deep. A module rail stands on the track.
const char* kRackScene = R"({
  "name": "rack",
  "scene": {
    "rack_walls": [{
      "center": [0, 0, 0], "normal": [1, 0, 0], "up": [0, 0, 1],
      "faces": [{"u": [-0.4, 1.0], "v": [-1.0, 0.05], "depth": 0.0},
                {"u": [-1.0, 0.3], "v": [0.09, 1.0], "depth": -0.03},
                {"u": [0.34, 1.0], "v": [0.09, 1.0], "depth": 0.02, "reflectivity": 0.4}],
      "seat_tracks": [{"from": [-0.6, 0.03], "to": [0.6, 0.03]}],
      "gaps": [{"u": [-1.0, 1.0], "v": [0.05, 0.09]},
               {"u": [0.3, 0.34], "v": [0.09, 1.0], "depth": -0.12}],
      "bays": [{"u": [-1.0, -0.4], "v": [-1.0, 0.05]}],
      "strips": [{"u": [-0.3, -0.2], "v": [-0.2, -0.15], "reflectivity": 0.9}]
    }],
    "handrails": [{"kind": "module_rail", "foot": [0.013, 0.0, 0.03], "normal": [1, 0, 0],
                   "axis": [0, 1, 0], "length": 1.0}]
  },
  "poses": [{"position": [0.6, 0, 0]}]
})";

Scenario load_text(const char* text) {
  Scenario s;
  std::string error;
  if (!parse_scenario(text, "rack.json", &s, &error)) print_error("%s\n", error.c_str());
  assert_true(error.empty());
  return s;
}

// The scene without its handrails: what their feet stand on.
Scene without_handrails(const Scene& scene) {
  Scene out = scene;
  out.surfaces.clear();
  for (const Surface& s : scene.surfaces)
    if (s.object_id < 0) out.surfaces.push_back(s);
  return out;
}

// Renders from 0.6 m in front of wall point (u, v) = world (y, z), looking
// straight at it, and returns the true range through the principal point's
// pixel (0 = no return).
struct CentreHit {
  float range_m;
  std::int32_t surface;
  hal::DepthPoint point;
};
CentreHit render_centre(const Scene& scene, double u, double v, const ToFSettings& settings) {
  const CameraIntrinsics cam = pico_flexx_intrinsics();
  DepthRenderer r(cam, settings);
  std::vector<hal::DepthPoint> pts;
  const Eigen::Isometry3d T = camera_pose(Eigen::Vector3d(0.6, u, v), Eigen::Vector3d(-1, 0, 0),
                                          Eigen::Vector3d(0, 0, 1), Eigen::Vector3d::Zero());
  r.render(scene, T, 7, 0, &pts);
  const std::size_t i = static_cast<std::size_t>(std::lround(cam.lens.cy_px)) * cam.width +
                        static_cast<std::size_t>(std::lround(cam.lens.cx_px));
  return {r.true_range_m()[i], r.hit_surface()[i], pts[i]};
}

void test_rack_wall_renders_its_depths(void**) {
  const Scenario sc = load_text(kRackScene);
  assert_int_equal(sc.scene.rack_walls.size(), 1);
  const Scene scene = without_handrails(sc.scene);
  struct Probe {
    const char* what;
    double u, v;
    bool returns;
    double depth_m;  // of the surface hit, along the wall normal
  } probes[] = {
      {"face A", 0.2, -0.4, true, 0.0},
      {"seat track top, 1.3 cm proud", 0.2, 0.03, true, 0.013},
      {"light strip, 3 mm proud", -0.25, -0.175, true, 0.003},
      {"opening above the track", 0.0, 0.07, false, 0.0},
      {"face B, 3 cm back", -0.2, 0.4, true, -0.03},
      {"face C, 2 cm proud", 0.6, 0.4, true, 0.02},
      {"gap between B and C, 12 cm back", 0.32, 0.4, true, -0.12},
      {"bay, 35 cm back", -0.7, -0.5, true, -0.35},
  };
  for (const Probe& p : probes) {
    const CentreHit h = render_centre(scene, p.u, p.v, all_off());
    print_message("%-34s range %.4f m, surface %d\n", p.what, h.range_m, h.surface);
    if (!p.returns) {
      assert_true(h.range_m == 0.0f);
      assert_int_equal(h.surface, -1);
      assert_int_equal(h.point.confidence, 0);
      continue;
    }
    // The principal point's pixel is within half a pixel of straight ahead.
    assert_near(h.range_m, 0.6 - p.depth_m, 1e-3);
    assert_near(h.point.z_m, 0.6 - p.depth_m, 1e-3);
  }
  // With every ToF effect on, the track still stands 1.3 cm proud of face A
  // within the noise (a few mm at 0.6 m), over the median of 9 frames.
  ToFSettings on;
  std::vector<float> z;
  const CameraIntrinsics cam = pico_flexx_intrinsics();
  DepthRenderer r(cam, on);
  std::vector<hal::DepthPoint> pts;
  const Eigen::Isometry3d T =
      camera_pose(Eigen::Vector3d(0.6, 0.2, 0.03), Eigen::Vector3d(-1, 0, 0),
                  Eigen::Vector3d(0, 0, 1), Eigen::Vector3d::Zero());
  const std::size_t i = static_cast<std::size_t>(std::lround(cam.lens.cy_px)) * cam.width +
                        static_cast<std::size_t>(std::lround(cam.lens.cx_px));
  for (std::uint64_t f = 0; f < 9; ++f) {
    r.render(scene, T, 3, f, &pts);
    if (hal::is_valid(pts[i])) z.push_back(pts[i].z_m);
  }
  assert_true(z.size() >= 7);
  std::sort(z.begin(), z.end());
  assert_near(z[z.size() / 2], 0.6 - 0.013, 0.004);
}

void test_handrail_on_a_seat_track(void**) {
  const Scenario sc = load_text(kRackScene);
  assert_int_equal(sc.scene.handrails.size(), 1);
  const Handrail& h = sc.scene.handrails[0];
  assert_int_equal(static_cast<int>(h.kind), static_cast<int>(HandrailKind::kModuleRail));
  assert_string_equal(to_string(h.kind), "module_rail");
  // The centre line: 6.1 cm above the track's top, 7.4 cm above face A.
  const RackWall& w = sc.scene.rack_walls[0];
  const double track_top = w.seat_tracks[0].top_depth_m();
  assert_near(track_top, 0.013, 1e-12);
  for (int e = 0; e < 2; ++e) {
    assert_near(h.end_point(e).x() - track_top, 0.061, 1e-9);
    assert_near(h.end_point(e).x(), 0.074, 1e-9);
  }
  // The truth from a camera 0.6 m off face A, straight in front of the rail.
  const CameraIntrinsics cam = pico_flexx_intrinsics();
  const Eigen::Isometry3d T =
      camera_pose(Eigen::Vector3d(0.6, 0.0, 0.03), Eigen::Vector3d(-1, 0, 0),
                  Eigen::Vector3d(0, 0, 1), Eigen::Vector3d::Zero());
  const FrameTruth t = compute_truth(sc.scene, cam, T, 0);
  assert_int_equal(t.handrails.size(), 1);
  const HandrailTruth& ht = t.handrails[0];
  assert_near(ht.center_cam.z(), 0.6 - 0.074, 1e-9);
  assert_near(ht.length_m, 1.0, 1e-12);
  assert_true(ht.visible_fraction > 0.5);
  // Its bar's front face renders where the truth says: 7.4 + 1.7 cm proud.
  const CentreHit bar = render_centre(sc.scene, 0.0, 0.03, all_off());
  assert_near(bar.range_m, 0.6 - 0.074 - 0.017, 1e-3);
  assert_true(sc.scene.surfaces[static_cast<std::size_t>(bar.surface)].object_id == 0);
}

// Where a handrail's feet are: a point inside each leg's footprint, and
// 1 cm to either side across the rail for the wider legs' edges.
std::vector<Eigen::Vector3d> foot_points(const Handrail& h) {
  const Eigen::Vector3d a = h.axis.normalized(), n = h.normal.normalized();
  const Eigen::Vector3d across = a.cross(n);
  std::vector<Eigen::Vector3d> out;
  for (double sign : {-1.0, 1.0}) {
    const Eigen::Vector3d leg = h.foot_center + sign * 0.5 * (h.bar_length_m - 0.045) * a;
    for (double c : {-0.008, 0.0, 0.008}) out.push_back(leg + c * across);
  }
  return out;
}

// A foot touches when the surface under it, with the handrail taken away,
// is where the foot is (within 3 mm).
bool feet_touch(const Scene& scene, const Handrail& h, std::string* why) {
  const Scene bare = without_handrails(scene);
  const Eigen::Vector3d n = h.normal.normalized();
  for (const Eigen::Vector3d& p : foot_points(h)) {
    Hit hit;
    const double lift = 0.05;
    if (!intersect_scene(bare, p + lift * n, -n, 1e-4, 1.0, &hit)) {
      *why = "nothing under a foot";
      return false;
    }
    if (std::fabs(hit.t - lift) > 0.003) {
      *why = "a foot is " + std::to_string(1000.0 * (hit.t - lift)) + " mm off the surface";
      return false;
    }
  }
  return true;
}

void test_every_kind_and_length(void**) {
  // The analytic ISS bar at the station's four lengths and the module
  // rail, each on the seat track: the truth's length, both ends in view
  // from far enough back, and a render of the bar's front face.
  const CameraIntrinsics cam = pico_flexx_intrinsics();
  struct Case {
    const char* kind;
    double length_m, front_offset_m;  // centre line to the bar's front face
  } cases[] = {{"iss", 0.20, 0.0175},
               {"iss", 0.53, 0.0175},
               {"iss", 0.76, 0.0175},
               {"iss", 1.04, 0.0175},
               {"module_rail", 1.0, 0.017}};
  for (const Case& c : cases) {
    std::string text = kRackScene;
    const std::string from = "\"kind\": \"module_rail\"",
                      to = std::string("\"kind\": \"") + c.kind + "\"";
    text.replace(text.find(from), from.size(), to);
    const std::string len_from = "\"length\": 1.0",
                      len_to = "\"length\": " + std::to_string(c.length_m);
    text.replace(text.find(len_from), len_from.size(), len_to);
    const Scenario sc = load_text(text.c_str());
    const Handrail& h = sc.scene.handrails[0];
    assert_near(h.bar_length_m, c.length_m, 1e-9);
    std::string why;
    if (!feet_touch(sc.scene, h, &why))
      print_error("%s %.2f: %s\n", c.kind, c.length_m, why.c_str());
    assert_true(why.empty());
    const Eigen::Isometry3d T =
        camera_pose(Eigen::Vector3d(1.3, 0.0, 0.03), Eigen::Vector3d(-1, 0, 0),
                    Eigen::Vector3d(0, 0, 1), Eigen::Vector3d::Zero());
    const FrameTruth t = compute_truth(sc.scene, cam, T, 0);
    assert_int_equal(t.handrails.size(), 1);
    assert_near((t.handrails[0].ends_cam[1] - t.handrails[0].ends_cam[0]).norm(), c.length_m, 1e-9);
    assert_true(t.handrails[0].end_in_view[0] && t.handrails[0].end_in_view[1]);
    // Off the legs (10 cm from the middle, inside even the 20 cm rail).
    const CentreHit bar = render_centre(sc.scene, 0.05, 0.03, all_off());
    assert_near(bar.range_m, 0.6 - 0.074 - c.front_offset_m, 1e-3);
  }
}

void test_every_shipped_handrail_stands_on_a_surface(void**) {
  const std::string dir = source_dir() + "/sim_hal/scenarios";
  DIR* d = opendir(dir.c_str());
  assert_non_null(d);
  int rails = 0, scenarios = 0;
  while (dirent* e = readdir(d)) {
    const std::string name = e->d_name;
    if (name.size() < 6 || name.compare(name.size() - 5, 5, ".json") != 0) continue;
    Scenario s;
    std::string error;
    if (!load_scenario(dir + "/" + name, &s, &error)) print_error("%s\n", error.c_str());
    assert_true(error.empty());
    ++scenarios;
    for (std::size_t k = 0; k < s.scene.handrails.size(); ++k) {
      // The module's own (its mesh's feet sink a few mm into its faces):
      // test_columbus_models_its_own_handrails measures them.
      if (s.scene.handrails[k].kind == HandrailKind::kInModuleMesh) continue;
      std::string why;
      if (!feet_touch(s.scene, s.scene.handrails[k], &why)) {
        print_error("%s: handrail %zu: %s\n", name.c_str(), k, why.c_str());
      }
      assert_true(why.empty());
      ++rails;
    }
  }
  closedir(d);
  print_message("%d handrails in %d scenarios stand on a surface\n", rails, scenarios);
  assert_true(rails >= 10);
}

void test_columbus_mesh_loads_with_its_documented_extent(void**) {
  const std::string path = source_dir() + "/sim_hal/assets/iss_modules/columbus_eu_lab.dae";
  const std::string text = std::string(R"({"name": "c", "scene": {"meshes": [{"path": ")") + path +
                           R"("}]}, "poses": [{"position": [0, 3, -0.44], "facing": [1, 0, 0]}]})";
  const Scenario sc = load_text(text.c_str());
  assert_int_equal(sc.scene.meshes.size(), 1);
  const TriangleMesh& m = *sc.scene.meshes[0].mesh;
  // Its README: metres, Z up kept (y the long axis 0.001 .. 6.03 m, x
  // -1.80 .. 1.80 m, z -2.03 .. 1.16 m), 4,088 triangles.
  print_message("%zu triangles, x %.3f .. %.3f, y %.3f .. %.3f, z %.3f .. %.3f\n",
                m.triangle_count(), m.min_corner().x(), m.max_corner().x(), m.min_corner().y(),
                m.max_corner().y(), m.min_corner().z(), m.max_corner().z());
  assert_true(m.triangle_count() > 4000 && m.triangle_count() <= 4088);
  assert_near(m.min_corner().x(), -1.80, 0.02);
  assert_near(m.max_corner().x(), 1.80, 0.02);
  assert_near(m.min_corner().y(), 0.001, 0.02);
  assert_near(m.max_corner().y(), 6.03, 0.02);
  assert_near(m.min_corner().z(), -2.03, 0.02);
  assert_near(m.max_corner().z(), 1.16, 0.02);
  // From its centre line, looking along +x at the starboard racks, most of
  // the view returns a wall within range, closer than the module's half
  // width, farther than its aisle.
  const CameraIntrinsics cam = pico_flexx_intrinsics();
  DepthRenderer r(cam, all_off());
  std::vector<hal::DepthPoint> pts;
  r.render(sc.scene, sc.T_world_cam[0], 1, 0, &pts);
  int hits = 0;
  for (std::size_t i = 0; i < pts.size(); ++i) {
    const float t = r.true_range_m()[i];
    if (t > 0.5f && t < 4.0f) ++hits;
  }
  print_message("%d of %zu pixels hit the module\n", hits, pts.size());
  assert_true(hits > static_cast<int>(pts.size()) / 2);
}

// The Columbus mesh models handrails of its own (a bar on two legs, feet
// and plates); the shipped scenes list them (mesh_handrails.py), and they
// become the scene's handrails: ground truth sees them, the camera sees
// what it saw before.
void test_columbus_models_its_own_handrails(void**) {
  Scenario sc;
  std::string error;
  const std::string dir = source_dir() + "/sim_hal/scenarios/";
  assert_true(load_scenario(dir + "columbus-module-views.json", &sc, &error));
  // The scenario's own four rails first, then the module's 34.
  assert_int_equal(sc.scene.handrails.size(), 4 + 34);
  for (std::size_t k = 0; k < 4; ++k) {
    assert_true(sc.scene.handrails[k].kind != HandrailKind::kInModuleMesh);
  }
  const Scene bare = without_handrails(sc.scene);
  int iss_like = 0;
  for (std::size_t k = 4; k < sc.scene.handrails.size(); ++k) {
    const Handrail& h = sc.scene.handrails[k];
    assert_int_equal(static_cast<int>(h.kind), static_cast<int>(HandrailKind::kInModuleMesh));
    assert_string_equal(to_string(h.kind), "in_module_mesh");
    assert_true(h.bar_length_m > 0.18 && h.bar_length_m < 1.08);
    // Its centre line stands off the face behind it (most as an ISS
    // handrail's, 6.1 to 6.3 cm), measured a quarter along the bar with the
    // handrails taken away; its bar's front is its own surface.
    const Eigen::Vector3d n = h.normal.normalized();
    const Eigen::Vector3d p = h.end_point(0) + 0.25 * (h.end_point(1) - h.end_point(0));
    Hit face, front;
    assert_true(intersect_scene(bare, p + 0.1 * n, -n, 1e-4, 1.0, &face));
    const double height_m = face.t - 0.1;
    assert_true(intersect_scene(sc.scene, p + 0.1 * n, -n, 1e-4, 1.0, &front));
    const double front_m = 0.1 - front.t;
    print_message(
        "module handrail %zu: %.3f m, centre line %.4f m off the face, front %.4f m "
        "before it\n",
        k, h.bar_length_m, height_m, front_m);
    // The faces behind some are recessed (up to 9.2 cm), one on the end
    // cone stands lower (3.1 cm); the sections are pointed hexagons.
    assert_true(height_m >= 0.03 && height_m <= 0.095);
    iss_like += height_m >= 0.055 && height_m <= 0.068;
    assert_int_equal(sc.scene.surfaces[static_cast<std::size_t>(front.surface)].object_id,
                     static_cast<int>(k));
    assert_true(front_m >= 0.004 && front_m <= 0.014);
  }
  print_message("%d of 34 stand 5.5 to 6.8 cm off the face behind them\n", iss_like);
  assert_true(iss_like >= 28);
}

// One of them, the 8.5 in rail on the starboard racks at y = 2.23, seen
// from 0.63 m: in the truth whole, both ends in view; the frame the same
// as with the mesh alone; a handrail placed where the mesh has none
// refused with the entry named.
void test_a_module_handrail_in_the_truth_and_the_frame_unchanged(void**) {
  const std::string mesh = source_dir() + "/sim_hal/assets/iss_modules/columbus_eu_lab.dae";
  const std::string head = R"({"name": "c", "scene": {"meshes": [{"path": ")" + mesh + "\"";
  const std::string tail =
      R"(}]}, "poses": [{"position": [0.35, 2.2257, -0.6055], "facing": [1, 0, 0]}]})";
  const std::string rail =
      R"(, "handrails": [{"ends": [[0.9813, 2.2257, -0.7059], [0.9813, 2.2257, -0.5046]],
                          "normal": [-1, 0, 0]}])";
  const Scenario with = load_text((head + rail + tail).c_str());
  const Scenario without = load_text((head + tail).c_str());
  assert_int_equal(with.scene.handrails.size(), 1);
  assert_int_equal(without.scene.handrails.size(), 0);
  const CameraIntrinsics cam = pico_flexx_intrinsics();
  const FrameTruth t = compute_truth(with.scene, cam, with.T_world_cam[0], 0);
  assert_int_equal(t.handrails.size(), 1);
  assert_near(t.handrails[0].length_m, 0.2013, 1e-3);
  assert_true(t.handrails[0].visible_fraction > 0.95);
  assert_true(t.handrails[0].end_in_view[0] && t.handrails[0].end_in_view[1]);
  assert_near(t.handrails[0].center_cam.z(), 0.9813 - 0.35, 1e-6);
  assert_int_equal(compute_truth(without.scene, cam, without.T_world_cam[0], 0).handrails.size(),
                   0);
  DepthRenderer a(cam, all_off()), b(cam, all_off());
  std::vector<hal::DepthPoint> pa, pb;
  a.render(with.scene, with.T_world_cam[0], 1, 0, &pa);
  b.render(without.scene, without.T_world_cam[0], 1, 0, &pb);
  int bar_pixels = 0;
  for (std::size_t i = 0; i < pa.size(); ++i) {
    assert_true(std::fabs(a.true_range_m()[i] - b.true_range_m()[i]) < 1e-5f);
    if (a.hit_surface()[i] >= 0) {
      bar_pixels +=
          with.scene.surfaces[static_cast<std::size_t>(a.hit_surface()[i])].object_id == 0;
    }
  }
  print_message("%d pixels on the module's handrail\n", bar_pixels);
  assert_true(bar_pixels > 300);
  // Ends in the aisle, where the mesh has nothing.
  const std::string stray =
      R"(, "handrails": [{"ends": [[0.0, 3.0, -0.44], [0.0, 3.5, -0.44]], "normal": [1, 0, 0]}])";
  Scenario bad;
  std::string error;
  assert_false(parse_scenario(head + stray + tail, "c.json", &bad, &error));
  print_message("refused: %s\n", error.c_str());
  assert_non_null(std::strstr(error.c_str(), "mesh handrail 0"));
  assert_non_null(std::strstr(error.c_str(), "c.json:"));
  // The same handrail with its normal into the wall: its box holds the bar
  // but not its legs; refused, the second entry named, nothing taken from
  // the module for the first.
  const std::string reversed =
      R"(, "handrails": [{"ends": [[0.9813, 2.2257, -0.7059], [0.9813, 2.2257, -0.5046]],
                          "normal": [-1, 0, 0]},
                         {"ends": [[0.9813, 2.2257, -0.7059], [0.9813, 2.2257, -0.5046]],
                          "normal": [1, 0, 0]}])";
  error.clear();
  assert_false(parse_scenario(head + reversed + tail, "c.json", &bad, &error));
  print_message("refused: %s\n", error.c_str());
  assert_non_null(std::strstr(error.c_str(), "mesh handrail 1"));
  Scene scene = without.scene;
  const std::size_t triangles = scene.meshes[0].mesh->triangle_count();
  MeshHandrail good, wrong;
  good.ends[0] = wrong.ends[0] = Eigen::Vector3d(0.9813, 2.2257, -0.7059);
  good.ends[1] = wrong.ends[1] = Eigen::Vector3d(0.9813, 2.2257, -0.5046);
  good.normal = Eigen::Vector3d(-1, 0, 0);
  wrong.normal = Eigen::Vector3d(1, 0, 0);
  assert_int_equal(scene.add_mesh_handrails(0, {good, wrong}), 1);
  assert_int_equal(scene.handrails.size(), 0);
  assert_int_equal(scene.meshes[0].mesh->triangle_count(), triangles);
  assert_int_equal(scene.add_mesh_handrails(0, {good}), -1);
  assert_int_equal(scene.handrails.size(), 1);
  assert_true(scene.meshes[0].mesh->triangle_count() < triangles);
  print_message("its centre line %.4f m off its feet\n", scene.handrails[0].center_offset_m());
  assert_true(scene.handrails[0].center_offset_m() > 0.055 &&
              scene.handrails[0].center_offset_m() < 0.07);
}

}  // namespace

int main() {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_rack_wall_renders_its_depths),
      cmocka_unit_test(test_handrail_on_a_seat_track),
      cmocka_unit_test(test_every_kind_and_length),
      cmocka_unit_test(test_every_shipped_handrail_stands_on_a_surface),
      cmocka_unit_test(test_columbus_mesh_loads_with_its_documented_extent),
      cmocka_unit_test(test_columbus_models_its_own_handrails),
      cmocka_unit_test(test_a_module_handrail_in_the_truth_and_the_frame_unchanged),
  };
  return cmocka_run_group_tests(tests, nullptr, nullptr);
}
