// The real ISS handrail meshes: loading, the bar as measured from them, the
// hierarchy against brute force, bad files, scenarios that use them, and a
// rendered mesh handrail found by the estimator where the truth says.
#include <Eigen/Geometry>
#include <Eigen/LU>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "cmocka_cpp.hpp"
#include "estimator/handrail_detector.hpp"
#include "frame_convert.hpp"
#include "sim_hal/ground_truth.hpp"
#include "sim_hal/mesh.hpp"
#include "sim_hal/scenario.hpp"
#include "sim_hal/sim_random.hpp"
#include "sim_hal/tof_sensor.hpp"

using namespace sim_hal;

namespace {

std::string mesh_path(const std::string& name) {
  const char* root = std::getenv("HRP_SOURCE_DIR");
  return std::string(root ? root : ".") + "/sim_hal/assets/handrails/" + name;
}

TriangleMesh load(const std::string& name, std::vector<Eigen::Vector3i>* triangles = nullptr) {
  std::vector<Eigen::Vector3d> v;
  std::vector<Eigen::Vector3i> t;
  std::string error;
  if (!load_collada_mesh(mesh_path(name), &v, &t, &error)) print_error("%s\n", error.c_str());
  assert_true(error.empty());
  if (triangles) *triangles = t;
  return TriangleMesh(v, t);
}

void test_meshes_load_with_the_bar_where_the_readme_says(void**) {
  struct Rail {
    const char* file;
    double bar_length_m;
  } rails[] = {{"handrail_8_5.dae", 0.202},
               {"handrail_21_5.dae", 0.531},
               {"handrail_30.dae", 0.762},
               {"handrail_41_5.dae", 1.040}};
  for (const Rail& r : rails) {
    const TriangleMesh mesh = load(r.file);
    assert_true(mesh.triangle_count() > 4000);
    // Z up kept: the long axis is z, x stands out of the wall.
    assert_true(mesh.max_corner().z() - mesh.min_corner().z() > 0.2);
    assert_near(mesh.max_corner().x(), 0.079, 0.002);
    const BarExtent bar = measure_bar(mesh, 0.046);
    assert_near(bar.center_offset_m(), 0.0615, 0.002);
    assert_near(bar.x_max - bar.x_min, 0.035, 0.002);
    assert_near(bar.y_max - bar.y_min, 0.019, 0.001);
    assert_near(bar.length_m(), r.bar_length_m, 0.005);
  }
}

// Brute force over every triangle, for comparison.
bool brute_force(const TriangleMesh& mesh, const std::vector<Eigen::Vector3i>& tris,
                 const Eigen::Vector3d& o, const Eigen::Vector3d& d, double* t_best) {
  bool any = false;
  *t_best = 1e9;
  for (const Eigen::Vector3i& tri : tris) {
    const Eigen::Vector3d& a = mesh.vertices()[static_cast<std::size_t>(tri[0])];
    const Eigen::Vector3d e1 = mesh.vertices()[static_cast<std::size_t>(tri[1])] - a;
    const Eigen::Vector3d e2 = mesh.vertices()[static_cast<std::size_t>(tri[2])] - a;
    Eigen::Matrix3d m;
    m << -d, e1, e2;
    if (std::fabs(m.determinant()) < 1e-14) continue;
    const Eigen::Vector3d x = m.inverse() * (o - a);  // t, u, v
    if (x[1] >= 0 && x[2] >= 0 && x[1] + x[2] <= 1 && x[0] > 0 && x[0] < *t_best) {
      *t_best = x[0];
      any = true;
    }
  }
  return any;
}

void test_hierarchy_matches_brute_force(void**) {
  std::vector<Eigen::Vector3i> tris;
  const TriangleMesh mesh = load("handrail_8_5.dae", &tris);
  SimRandom rng(5);
  const Eigen::Vector3d lo = mesh.min_corner(), hi = mesh.max_corner();
  int hits = 0;
  for (int k = 0; k < 400; ++k) {
    // From a point around the rail toward a point in its box.
    const Eigen::Vector3d target(lo.x() + rng.uniform() * (hi.x() - lo.x()),
                                 lo.y() + rng.uniform() * (hi.y() - lo.y()),
                                 lo.z() + rng.uniform() * (hi.z() - lo.z()));
    const Eigen::Vector3d from(0.3 * (rng.uniform() - 0.2), 0.3 * (rng.uniform() - 0.5),
                               0.3 * (rng.uniform() - 0.5));
    const Eigen::Vector3d d = (target - from).normalized();
    MeshHit hit;
    double t_ref = 0.0;
    const bool got = mesh.intersect(from, d, 0.0, 10.0, &hit);
    const bool want = brute_force(mesh, tris, from, d, &t_ref);
    assert_int_equal(got, want);
    if (got) {
      ++hits;
      // The walk is in single precision: a micrometre at these ranges.
      assert_near(hit.t, t_ref, 1e-6);
      assert_near(hit.normal.norm(), 1.0, 1e-6);
    }
  }
  assert_true(hits > 50);
}

void test_bad_mesh_files_are_reported(void**) {
  std::vector<Eigen::Vector3d> v;
  std::vector<Eigen::Vector3i> t;
  std::string error;
  assert_false(load_collada_mesh("/nonexistent/rail.dae", &v, &t, &error));
  assert_non_null(std::strstr(error.c_str(), "/nonexistent/rail.dae: cannot load mesh"));
  const std::string junk = "/tmp/hrp_test_junk.dae";
  std::FILE* f = std::fopen(junk.c_str(), "w");
  assert_non_null(f);
  std::fputs("<COLLADA><library_geometries><oops", f);
  std::fclose(f);
  error.clear();
  assert_false(load_collada_mesh(junk, &v, &t, &error));
  assert_non_null(std::strstr(error.c_str(), junk.c_str()));
  std::remove(junk.c_str());
}

std::string mesh_scenario(const std::string& rail) {
  return "{\n \"name\": \"m\",\n \"scene\": {\"walls\": [{\"center\": [0, 0, 0], \"normal\": [1, "
         "0, "
         "0], \"size\": [2, 2]}],\n  \"handrails\": [\n   " +
         rail + "]},\n \"poses\": [{\"position\": [0.6, 0, 0]}]\n}";
}

void test_mesh_scenario_errors(void**) {
  const std::string scenario_file = mesh_path("s.json");  // meshes resolve beside it
  struct Case {
    std::string rail;
    std::string error;
  } cases[] = {
      {"{\"kind\": \"iss_mesh\", \"foot\": [0,0,0], \"normal\": [1,0,0], \"axis\": [0,1,0], "
       "\"mesh\": \"handrail_21_5.dae\", \"length\": 0.5}",
       scenario_file +
           ":5: an \"iss_mesh\" handrail takes its length from the mesh: drop \"length\""},
      {"{\"kind\": \"iss_mesh\", \"foot\": [0,0,0], \"normal\": [1,0,0], \"axis\": [0,1,0]}",
       scenario_file + ":5: missing \"mesh\""},
      {"{\"kind\": \"iss\", \"foot\": [0,0,0], \"normal\": [1,0,0], \"axis\": [0,1,0], "
       "\"length\": 0.5, \"mesh\": \"handrail_21_5.dae\"}",
       scenario_file + ":5: \"mesh\" is for \"iss_mesh\" handrails only"},
      {"{\"kind\": \"iss_mesh\", \"foot\": [0,0,0], \"normal\": [1,0,0], \"axis\": [0,1,0], "
       "\"mesh\": \"missing.dae\"}",
       scenario_file + ":5: " + mesh_path("missing.dae") + ": cannot load mesh"},
  };
  for (const Case& c : cases) {
    Scenario s;
    std::string error;
    assert_false(parse_scenario(mesh_scenario(c.rail), scenario_file, &s, &error));
    if (error.compare(0, c.error.size(), c.error) != 0) {
      print_error("got: %s\nwant: %s...\n", error.c_str(), c.error.c_str());
    }
    assert_true(error.compare(0, c.error.size(), c.error) == 0);
  }
}

void test_rendered_mesh_rail_is_found_where_the_truth_says(void**) {
  Scenario s;
  std::string error;
  const std::string rail =
      "{\"kind\": \"iss_mesh\", \"foot\": [0,0,0], \"normal\": [1,0,0], \"axis\": [0,1,0], "
      "\"mesh\": \"handrail_21_5.dae\"}";
  assert_true(parse_scenario(mesh_scenario(rail), mesh_path("s.json"), &s, &error));
  const Handrail& h = s.scene.handrails[0];
  assert_int_equal(static_cast<int>(h.kind), static_cast<int>(HandrailKind::kIssMesh));
  assert_near(h.bar_length_m, 0.531, 0.005);

  const CameraIntrinsics cam = pico_flexx_intrinsics();
  DepthRenderer renderer(cam, s.sensor);
  std::vector<hal::DepthPoint> pts;
  renderer.render(s.scene, s.T_world_cam[0], s.seed, 0, &pts);
  const FrameTruth truth = compute_truth(s.scene, cam, s.T_world_cam[0], 0);
  assert_int_equal(truth.handrails.size(), 1);

  // The bar's image is as wide as 1.9 cm at its range (the centre column).
  const int col = static_cast<int>(std::lround(cam.lens.cx_px));
  int raised = 0;
  for (int row = 0; row < static_cast<int>(cam.height); ++row) {
    const hal::DepthPoint& p = pts[static_cast<std::size_t>(row) * cam.width + col];
    raised += hal::is_valid(p) && p.z_m < 0.6f - 0.03f;
  }
  assert_near(raised, cam.lens.fy_px * 0.019 / (0.6 - 0.079), 2.0);

  hal::DepthFrame frame;
  frame.width = cam.width;
  frame.height = cam.height;
  frame.points = pts.data();
  std::vector<estimator::CloudPoint> buffer;
  const estimator::OrganizedCloud cloud = tools::to_estimator_cloud(frame, &buffer);
  estimator::DetectorConfig cfg;
  cfg.gripper_angle_rad = static_cast<float>(M_PI / 2);
  estimator::HandrailDetector detector(cfg);
  const estimator::HandrailDetection d = detector.detect(cloud);
  assert_int_equal(static_cast<int>(d.status), static_cast<int>(estimator::DetectStatus::kFound));
  const Eigen::Vector3d center =
      0.5 * (truth.handrails[0].ends_cam[0] + truth.handrails[0].ends_cam[1]);
  assert_true((d.p_cam_center.cast<double>() - center).norm() < 0.005);
}

}  // namespace

int main() {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_meshes_load_with_the_bar_where_the_readme_says),
      cmocka_unit_test(test_hierarchy_matches_brute_force),
      cmocka_unit_test(test_bad_mesh_files_are_reported),
      cmocka_unit_test(test_mesh_scenario_errors),
      cmocka_unit_test(test_rendered_mesh_rail_is_found_where_the_truth_says),
  };
  return cmocka_run_group_tests(tests, nullptr, nullptr);
}
