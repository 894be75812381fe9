#pragma once
// A map of one handrail: its pose in the world, taken from its first
// confident sightings and then held fixed while perching.
//
// A sighting is T_world_handrail = T_world_body(capture) T_body_cam
// T_cam_handrail: the filter's pose at the frame's capture time, the camera
// mount (eq. 7) and the detected handrail frame (eq. 5). Only a sighting with
// an end seen (BE or OE) places the handrail along its axis, so only those
// build the map, and only while the filter's position sigma is below
// map_init_max_position_sigma_m. The map is the mean of map_init_sightings
// sightings that agree with their running mean within map_consistency_m and
// map_consistency_rad; one that does not restarts the count from itself.
//
// Held fixed, the map carries the filter's world error at the time it was
// built (the GP's bias, a few cm): the pose relative to the handrail, which
// perching needs, is then as good as the handrail updates, while the pose in
// the world stays as good as the GP.
//
// A surveyed map is given instead (the station's handrails sit at known rack
// positions; the paper's table test had its handrail at a known place): the
// handrail's world pose with the survey's uncertainty. The handrail then
// places the robot in the world, to the survey's accuracy. Its uncertainty
// enters each feature's residual noise (handrail_update.hpp); a surveyed
// map is never rebuilt from sightings.
#include <Eigen/Geometry>

#include "estimator/localization/config.hpp"
#include "estimator/localization/status.hpp"

namespace estimator::localization {

struct HandrailMap {
  bool valid = false;
  bool surveyed = false;  // given, not built from sightings
  Eigen::Isometry3d T_world_handrail = Eigen::Isometry3d::Identity();
  // The survey's 1-sigma uncertainty, per axis (0 for a map from sightings,
  // whose error is the filter's own at the time, already in its state).
  double position_sigma_m = 0.0;
  double attitude_sigma_rad = 0.0;
};

// kAccepted for a usable survey: T_world_handrail finite, a rotation (within
// 1e-6) and within 1000 m; sigmas finite, 0 to 1 m and 0 to 1 rad.
// Otherwise kRejectedNotFinite or kRejectedInvalid.
UpdateStatus check_survey(const HandrailMap& survey);

// The handrail frame turned by pi about its x axis (the wall normal): the
// same bar with its axis the other way (y and z negated). A detector fixes
// the axis sign by the image, which a turn of the robot can reverse.
Eigen::Matrix3d flip_axis(const Eigen::Matrix3d& R_x_handrail);

class HandrailMapBuilder {
 public:
  void reset();
  // kMapSighting while counting, kMapInitialized on the sighting that
  // completes the map. *restarted is set when this sighting disagreed with
  // the ones before and the count restarted from it.
  UpdateStatus add_sighting(const LocalizationConfig& cfg,
                            const Eigen::Isometry3d& T_world_handrail, bool* restarted);
  // Installs a checked survey as the map (valid, surveyed).
  void set_survey(const HandrailMap& survey);
  const HandrailMap& map() const { return map_; }
  int sightings() const { return count_; }

 private:
  void start(const Eigen::Isometry3d& T);
  HandrailMap map_;
  int count_ = 0;
  Eigen::Vector3d sum_p_ = Eigen::Vector3d::Zero();
  Eigen::Vector4d sum_q_ = Eigen::Vector4d::Zero();  // quaternion coefficients, one hemisphere
  Eigen::Vector3d mean_p_ = Eigen::Vector3d::Zero();
  Eigen::Quaterniond mean_q_ = Eigen::Quaterniond::Identity();
};

}  // namespace estimator::localization
