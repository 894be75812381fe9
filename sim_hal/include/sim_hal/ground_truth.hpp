#pragma once
// What the detector should find in a frame, from the scene itself.
#include <Eigen/Geometry>
#include <cstdint>
#include <string>
#include <vector>

#include "sim_hal/camera_model.hpp"
#include "sim_hal/scene.hpp"

namespace sim_hal {

struct HandrailTruth {
  int index = 0;  // in Scene::handrails
  HandrailKind kind = HandrailKind::kIss;
  Eigen::Vector3d ends_cam[2];  // centre-line end points, camera frame
  Eigen::Vector3d center_cam;   // midway between them
  Eigen::Vector3d axis_cam;     // from end 0 to end 1
  Eigen::Vector3d normal_cam;   // wall normal, toward the room
  double length_m = 0.0;
  double visible_fraction = 0.0;  // of the centre line, in the image and unoccluded
  // The middle of the visible samples of the centre line, camera frame (the
  // centre when nothing hides it): how far away the part in view is.
  Eigen::Vector3d visible_center_cam = Eigen::Vector3d::Zero();
  bool end_in_view[2] = {false, false};
};

struct FrameTruth {
  std::uint64_t frame = 0;
  Eigen::Isometry3d T_world_cam = Eigen::Isometry3d::Identity();
  std::vector<HandrailTruth> handrails;  // only those with any part in view
};

FrameTruth compute_truth(const Scene& scene, const CameraIntrinsics& cam,
                         const Eigen::Isometry3d& T_world_cam, std::uint64_t frame);

// One JSON object on one line (the format of truth.jsonl; see README).
std::string truth_to_json(const FrameTruth& truth, const std::string& frame_file);

}  // namespace sim_hal
