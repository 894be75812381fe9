#pragma once
// How well the robot knew where it was: the localization filter's pose
// (ROBOT_POSE) and the general-purpose localizer's fixes (GP_POSE) against
// the simulator's truth, over the approach and at the grasp. Filled by the
// hardware-in-loop world (hil/hil_sensors.hpp), reported by the run summary.
#include <cstdint>

namespace fsw_app {

// Position and attitude errors of one pose source over a phase.
struct PoseErrorStats {
  std::int64_t samples = 0;
  double mean_m = 0.0, max_m = 0.0;
  double mean_deg = 0.0, max_deg = 0.0;
  void add(double e_m, double e_deg) {
    ++samples;
    const double n = static_cast<double>(samples);
    mean_m += (e_m - mean_m) / n;
    mean_deg += (e_deg - mean_deg) / n;
    max_m = e_m > max_m ? e_m : max_m;
    max_deg = e_deg > max_deg ? e_deg : max_deg;
  }
};

// The normalized estimation error squared of a pose source that claims a
// covariance: e^T P^-1 e for its position (3 degrees of freedom, world) and
// its attitude (3, world axes), per pose, averaged over a phase. A
// consistent filter averages 3 on each; far above 3 it is overconfident.
struct NeesStats {
  std::int64_t samples = 0;
  double mean_position = 0.0, mean_attitude = 0.0;
  double max_position = 0.0, max_attitude = 0.0;
  void add(double position, double attitude) {
    ++samples;
    const double n = static_cast<double>(samples);
    mean_position += (position - mean_position) / n;
    mean_attitude += (attitude - mean_attitude) / n;
    max_position = position > max_position ? position : max_position;
    max_attitude = attitude > max_attitude ? attitude : max_attitude;
  }
};

struct LocalizationScore {
  PoseErrorStats filter_approach, gp_approach;
  NeesStats filter_nees_approach;                         // the filter's poses over the approach
  bool at_grasp = false;                                  // the grip closed while scoring
  double filter_grasp_m = -1.0, filter_grasp_deg = -1.0;  // the filter's newest at the grasp
  double gp_grasp_m = -1.0, gp_grasp_deg = -1.0;          // the newest GP fix at the grasp
  std::int64_t filter_poses = 0;      // ROBOT_POSE messages from the filter (any time)
  std::int64_t non_filter_poses = 0;  // ROBOT_POSE from another source
  std::uint64_t imu_samples = 0, gp_fixes = 0, gp_dropped = 0;
};

}  // namespace fsw_app
