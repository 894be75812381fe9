#pragma once
// A module's views (sim_hal/scenarios/<module>-views.json) through a
// detector configuration, scored against the labelled rails: what the
// module-scene tests share.
#include <Eigen/Geometry>
#include <cmath>
#include <cstdlib>
#include <string>

#include "cmocka_cpp.hpp"
#include "rack_test_scenes.hpp"

namespace moduleviews {

inline sim_hal::Scenario load_views(const char* file_name) {
  sim_hal::Scenario sc;
  std::string error;
  const char* root = std::getenv("HRP_SOURCE_DIR");
  const std::string path = std::string(root ? root : ".") + "/sim_hal/scenarios/" + file_name;
  if (!sim_hal::load_scenario(path, &sc, &error)) fail_msg("%s", error.c_str());
  return sc;
}

struct Finds {
  int rail_frames = 0, right = 0, wrong = 0;  // frames with a rail 35 % in view
  int empty_frames = 0, false_finds = 0;      // frames with no rail in view
};

// A find is right when its centre lies within 5 cm of a labelled rail's
// centre line and its axis within 15 deg of that rail's.
inline bool on_a_rail(const estimator::HandrailDetection& d, const sim_hal::FrameTruth& truth) {
  for (const sim_hal::HandrailTruth& t : truth.handrails) {
    const Eigen::Vector3d p = d.p_cam_center.cast<double>() - t.center_cam;
    const double off_m = (p - p.dot(t.axis_cam) * t.axis_cam).norm();
    const double cos_axis = std::fabs(d.axis().cast<double>().dot(t.axis_cam));
    if (off_m < 0.05 && cos_axis > std::cos(15.0 * M_PI / 180.0)) return true;
  }
  return false;
}

inline Finds detect_views(const sim_hal::Scenario& sc, const estimator::DetectorConfig& cfg) {
  estimator::HandrailDetector detector(cfg);
  const sim_hal::CameraIntrinsics cam = sim_hal::pico_flexx_intrinsics();
  racktest::Rendered r;
  Finds out;
  for (std::size_t f = 0; f < sc.T_world_cam.size(); ++f) {
    racktest::render_scene(sc.scene, sc.T_world_cam[f], f, &r);
    const sim_hal::FrameTruth truth = sim_hal::compute_truth(sc.scene, cam, sc.T_world_cam[f], f);
    double most_visible = 0.0;
    for (const sim_hal::HandrailTruth& t : truth.handrails) {
      most_visible = std::fmax(most_visible, t.visible_fraction);
    }
    const estimator::HandrailDetection d = detector.detect(r.cloud);
    const bool found = d.status == estimator::DetectStatus::kFound;
    if (most_visible == 0.0) {
      ++out.empty_frames;
      out.false_finds += found;
    } else if (most_visible >= 0.35) {
      ++out.rail_frames;
      if (found) ++(on_a_rail(d, truth) ? out.right : out.wrong);
    }
  }
  return out;
}

}  // namespace moduleviews
