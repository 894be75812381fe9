// The ISS module scenes (Node 1, 2, 3 and the Cupola): every handrail the
// module mesh models is labelled and loads as ground truth, each label
// lies on the mesh's bar, the views meant to show no handrail show none,
// and the views of a rail show one.
#include <cmath>
#include <cstdlib>
#include <string>

#include "cmocka_cpp.hpp"
#include "sim_hal/ground_truth.hpp"
#include "sim_hal/scenario.hpp"

namespace {

std::string scenario_path(const char* name) {
  const char* root = std::getenv("HRP_SOURCE_DIR");
  return std::string(root ? root : ".") + "/sim_hal/scenarios/" + name;
}

struct ModuleScene {
  const char* file;
  int labelled_rails;  // obj_handrails.py's count (bars on two legs)
};
constexpr ModuleScene kModules[] = {{"node1-views.json", 15},
                                    {"node2-views.json", 10},
                                    {"node3-views.json", 14},
                                    {"cupola-views.json", 6}};

sim_hal::Scenario load(const char* name) {
  sim_hal::Scenario sc;
  std::string error;
  if (!sim_hal::load_scenario(scenario_path(name), &sc, &error)) {
    fail_msg("%s: %s", name, error.c_str());
  }
  return sc;
}

void test_every_modelled_rail_is_labelled_and_loads(void**) {
  for (const ModuleScene& m : kModules) {
    const sim_hal::Scenario sc = load(m.file);
    int in_mesh = 0;
    for (const sim_hal::Handrail& h : sc.scene.handrails) {
      in_mesh += h.kind == sim_hal::HandrailKind::kInModuleMesh;
    }
    if (in_mesh != m.labelled_rails) {
      fail_msg("%s: %d rails labelled, expected %d", m.file, in_mesh, m.labelled_rails);
    }
  }
}

// A ray cast toward a label's centre line, along its normal from 8 cm out,
// meets the mesh's bar between 0.5 and 3 cm in front of the line (the
// bar's front face stands half its 3.3 to 3.7 cm depth in front of it).
void test_each_label_lies_on_the_mesh_bar(void**) {
  for (const ModuleScene& m : kModules) {
    const sim_hal::Scenario sc = load(m.file);
    for (std::size_t k = 0; k < sc.scene.handrails.size(); ++k) {
      const sim_hal::Handrail& h = sc.scene.handrails[k];
      if (h.kind != sim_hal::HandrailKind::kInModuleMesh) continue;
      const Eigen::Vector3d centre = 0.5 * (h.end_point(0) + h.end_point(1));
      const Eigen::Vector3d n = h.normal.normalized();
      constexpr double kStart_m = 0.08;
      sim_hal::Hit hit;
      if (!sim_hal::intersect_scene(sc.scene, centre + kStart_m * n, -n, 0.0, 1.0, &hit)) {
        fail_msg("%s rail %zu: nothing behind its label", m.file, k);
      }
      const double front_m = kStart_m - hit.t;
      if (!(front_m > 0.005 && front_m < 0.03)) {
        fail_msg("%s rail %zu: the surface met stands %.1f mm in front of the centre line", m.file,
                 k, 1000.0 * front_m);
      }
    }
  }
}

// The truth of each frame: the no-handrail views show no handrail at all;
// the views of a rail show a handrail at least 30 % visible in most frames
// (partial views show less by design).
void test_views_show_what_their_labels_say(void**) {
  const sim_hal::CameraIntrinsics cam = sim_hal::pico_flexx_intrinsics();
  for (const ModuleScene& m : kModules) {
    const sim_hal::Scenario sc = load(m.file);
    int rail_frames = 0, rail_frames_in_view = 0, empty_frames = 0;
    for (std::size_t f = 0; f < sc.T_world_cam.size(); ++f) {
      const sim_hal::FrameTruth truth = sim_hal::compute_truth(sc.scene, cam, sc.T_world_cam[f], f);
      double most_visible = 0.0;
      for (const sim_hal::HandrailTruth& h : truth.handrails) {
        most_visible = std::fmax(most_visible, h.visible_fraction);
      }
      if (sc.pose_labels[f].find("no-handrail") != std::string::npos) {
        ++empty_frames;
        if (most_visible > 0.0) {
          fail_msg("%s frame %zu (%s): a handrail %.0f %% in view", m.file, f,
                   sc.pose_labels[f].c_str(), 100.0 * most_visible);
        }
      } else {
        ++rail_frames;
        rail_frames_in_view += most_visible >= 0.3;
      }
    }
    if (empty_frames < 12 || rail_frames < 80 || rail_frames_in_view < 0.9 * rail_frames) {
      fail_msg("%s: %d empty views, %d of %d rail views with a rail 30 %% in view", m.file,
               empty_frames, rail_frames_in_view, rail_frames);
    }
  }
}

}  // namespace

int main() {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_every_modelled_rail_is_labelled_and_loads),
      cmocka_unit_test(test_each_label_lies_on_the_mesh_bar),
      cmocka_unit_test(test_views_show_what_their_labels_say),
  };
  return cmocka_run_group_tests(tests, nullptr, nullptr);
}
