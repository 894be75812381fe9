#pragma once
// A map of one handrail: its pose in the world, taken from its first
// confident sightings (or a survey), then put into the filter's state
// (map_state.hpp), where it keeps the uncertainty it was built with.
//
// A sighting is T_world_handrail = T_world_body(capture) T_body_cam
// T_cam_handrail: the filter's pose at the frame's capture time, the camera
// mount (eq. 7) and the detected handrail frame (eq. 5). Sightings count
// only while the filter's position sigma is below
// map_init_max_position_sigma_m. The map is the mean of map_init_sightings
// sightings that agree with their running mean within map_consistency_m and
// map_consistency_rad; one that does not restarts the count from itself.
// Only a sighting with an end seen (BE, or OE with a known length) places
// the handrail along its axis. Sightings with none build a line map: they
// agree across the bar only, and its origin is where the first one put it,
// somewhere on the bar. That is all an NE update needs, so the handrail
// holds the pose across the bar from the first frames; the filter replaces
// the line map by one with ends once enough sightings with ends agree.
//
// A surveyed map is given instead (the station's handrails sit at known rack
// positions; the paper's table test had its handrail at a known place): the
// handrail's world pose with the survey's uncertainty. The handrail then
// places the robot in the world, to the survey's accuracy. A surveyed map
// is never rebuilt from sightings.
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
  // False for a line map: built from sightings with no end seen, its origin
  // is somewhere on the bar's line (where the first one saw it). NE updates
  // need no more (they hold nothing along the bar); sightings with an end
  // replace it by a map placed along the bar once enough of them agree.
  bool along_known = true;
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
  // the ones before and the count restarted from it. along_known: the
  // sighting saw an end (BE, OE). Sightings with ends build a map; without,
  // a line map, whose sightings need agree only across the bar (their
  // origins slide along it) and which keeps the first one's origin. A
  // sighting with an end restarts a count of sightings without; one without
  // during a count with ends is refused (kNoMap), nothing changed.
  UpdateStatus add_sighting(const LocalizationConfig& cfg,
                            const Eigen::Isometry3d& T_world_handrail, bool along_known,
                            bool* restarted);
  // Installs a checked survey as the map (valid, surveyed).
  void set_survey(const HandrailMap& survey);
  const HandrailMap& map() const { return map_; }
  int sightings() const { return count_; }

 private:
  void start(const Eigen::Isometry3d& T, bool along_known);
  HandrailMap map_;
  int count_ = 0;
  bool counting_along_known_ = true;
  Eigen::Vector3d first_p_ = Eigen::Vector3d::Zero();  // a line map's origin
  Eigen::Vector3d sum_p_ = Eigen::Vector3d::Zero();
  Eigen::Vector4d sum_q_ = Eigen::Vector4d::Zero();  // quaternion coefficients, one hemisphere
  Eigen::Vector3d mean_p_ = Eigen::Vector3d::Zero();
  Eigen::Quaterniond mean_q_ = Eigen::Quaterniond::Identity();
};

}  // namespace estimator::localization
