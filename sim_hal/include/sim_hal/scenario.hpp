#pragma once
// Scenario files (JSON): a scene, a list of camera poses, sensor settings
// and a seed. The format is documented in sim_hal/README.md.
#include <Eigen/Geometry>
#include <cstdint>
#include <string>
#include <vector>

#include "sim_hal/scene.hpp"
#include "sim_hal/tof_sensor.hpp"

namespace sim_hal {

struct Scenario {
  std::string name;
  std::string description;
  std::uint64_t seed = 1;
  double frame_rate_hz = 5.0;
  // The angle of handrails the gripper takes (0 = along the image's y
  // axis); evaluation picks the target handrail by it.
  double gripper_angle_deg = 0.0;
  ToFSettings sensor;
  Scene scene;
  std::vector<Eigen::Isometry3d> T_world_cam;  // one per frame
  std::vector<std::string> pose_labels;        // one per frame, e.g. "table2-3"
};

// Camera orientation from a body pose: body x forward, y left, z up, turned
// by roll (about x), pitch (about y, positive looks down), yaw (about z,
// positive turns left) from a base that faces `facing` with `up` up. The
// camera's optical frame is x right, y down, z forward.
Eigen::Isometry3d camera_pose(const Eigen::Vector3d& position, const Eigen::Vector3d& facing,
                              const Eigen::Vector3d& up, const Eigen::Vector3d& rpy_deg);

// Loads and checks a scenario. On failure returns false with *error as
// "FILE:LINE: what is wrong".
bool load_scenario(const std::string& path, Scenario* out, std::string* error);
bool parse_scenario(const std::string& text, const std::string& path, Scenario* out,
                    std::string* error);

}  // namespace sim_hal
