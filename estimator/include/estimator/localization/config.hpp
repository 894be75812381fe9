#pragma once
// Every number the localization filter uses. Defaults in
// estimator/doc/localization.md; validate() names the first field out of range.
#include <Eigen/Core>
#include <Eigen/Geometry>

namespace estimator::localization {

// Fixed sizes: everything the filter holds is sized by these at compile time.
constexpr int kHistoryCapacity = 64;        // IMU samples with state and covariance
                                            // (1.0 s at 62.5 Hz: a 300 ms late pose fits)
constexpr int kMaxStoredMeasurements = 16;  // accepted updates kept for re-propagation
constexpr int kMaxUsedBarFeatures = 12;     // per handrail update, after thinning
constexpr int kMaxUsedWallFeatures = 8;
constexpr int kMaxUsedFeatures = kMaxUsedBarFeatures + kMaxUsedWallFeatures;
constexpr int kMaxGapSubsteps = 128;  // bounds max_imu_gap_s * imu_rate_hz

// Continuous-time IMU noise (densities; a sample at rate f has a white
// noise of density * sqrt(f)). The defaults are an Epson G362-class IMU as on
// Astrobee, with margin for fan and propulsion vibration.
struct ImuNoise {
  double gyro_noise_radps_rthz = 1e-4;     // angle random walk
  double accel_noise_mps2_rthz = 2e-3;     // velocity random walk
  double gyro_bias_rw_radps2_rthz = 1e-6;  // bias random walks
  double accel_bias_rw_mps3_rthz = 1e-4;
};

// Body from camera as on the robot's camera mount (the same numbers as
// fsw_app's default; the application sets it from its configuration).
Eigen::Isometry3d default_T_body_cam();

struct LocalizationConfig {
  ImuNoise imu;
  double imu_rate_hz = 62.5;  // Astrobee's filter rate; sizes the gap sub-steps

  // IMU gaps (the rule, in imu_propagation.hpp):
  //   dt <= max_imu_step_s               one step;
  //   max_imu_step_s < dt <= max_imu_gap_s  bridged in sub-steps of at most
  //       1 / imu_rate_hz with the two bounding samples interpolated, plus the
  //       unmeasured-motion noise below (the IMU did not see that motion);
  //   dt > max_imu_gap_s                 not integrated: position, velocity and
  //       attitude held, covariance inflated by the lost_* sigmas, the
  //       estimate flagged lost until a GP or handrail update is accepted.
  double max_imu_step_s = 0.05;
  double max_imu_gap_s = 1.0;
  double gap_accel_sigma_mps2_rthz = 0.02;
  double gap_rate_sigma_radps_rthz = 0.01;
  double lost_position_sigma_m = 0.5;
  double lost_attitude_sigma_rad = 0.2;
  double lost_velocity_sigma_mps = 0.1;
  // A sample beyond the sensor's range is a fault, not motion.
  double max_rate_radps = 10.0;
  double max_accel_mps2 = 40.0;
  // Gravity in the world frame: zero in the ISS (free fall; the accelerometer
  // feels only thrust). A test on a granite table would set (0, 0, -9.81).
  Eigen::Vector3d g_world_mps2 = Eigen::Vector3d::Zero();

  // Start from the first GP pose: its pose covariance, these for the rest.
  double init_velocity_sigma_mps = 0.05;
  double init_gyro_bias_sigma_radps = 0.005;
  double init_accel_bias_sigma_mps2 = 0.05;
  Eigen::Vector3d init_gyro_bias_radps = Eigen::Vector3d::Zero();
  Eigen::Vector3d init_accel_bias_mps2 = Eigen::Vector3d::Zero();

  // A measurement captured up to this long after the newest IMU sample is
  // applied at the newest sample (IMU and camera clocks jitter); later ones
  // are rejected. Older than the history (kHistoryCapacity samples): too old.
  double max_future_s = 0.02;

  // Chi-square gate: the probability of the gate's region; the threshold is
  // the quantile for the measurement's dimension (gates.hpp).
  double gate_probability = 0.999;

  // GP relocalisation (the rule, in localization_filter.hpp): a GP pose
  // rejected by the gate, then poses agreeing with its jump (within these),
  // this many in a row with no handrail holding the pose: the filter moves
  // to the GP pose.
  int relocalize_after = 3;
  double relocalize_agreement_m = 0.05;
  double relocalize_agreement_rad = 0.05;
  // Divergence (the rule, in localization_filter.hpp): this many GP poses
  // in a row rejected, whatever their offsets, with no handrail holding the
  // pose: the filter starts again from the GP pose, velocity and biases too.
  int reinitialize_after = 6;

  // Handrail measurements.
  Eigen::Isometry3d T_body_cam = default_T_body_cam();
  // Noise of one feature's residual. The residuals of one frame are not
  // independent (they share the detected pose, eq. 8); these are set so that
  // a frame of 12 features carries about what the detection knows.
  double bar_feature_sigma_m = 0.004;
  double wall_feature_sigma_m = 0.006;
  int max_bar_features = 8;   // used per update, at most kMaxUsedBarFeatures
  int max_wall_features = 4;  // at most kMaxUsedWallFeatures
  int min_features = 4;       // fewer after the per-feature gate: rejected
  // NE: set each feature's along-bar coordinate to the predicted one before
  // the residual, so that the component eq. 13 drops is zero and nothing of
  // the detection's arbitrary along-bar origin leaks into the two kept ones
  // through the small angle between the detected and the mapped axis.
  bool ne_reanchor_along_bar = true;

  // The handrail map (handrail_map.hpp): built from this many consistent
  // sightings with an end seen (BE or OE) while the filter's position sigma
  // is below map_init_max_position_sigma_m, then held; dropped after
  // map_reset_after_rejections handrail updates in a row fail the gate.
  int map_init_sightings = 3;
  double map_consistency_m = 0.03;
  double map_consistency_rad = 0.05;
  double map_init_max_position_sigma_m = 0.25;
  int map_reset_after_rejections = 10;
  // A map from sightings is uncertain by the robot's pose at the time
  // (correlated with it, map_state.hpp) and by the detections' own error,
  // these 1-sigma, per axis: the bar's position (across a few mm, along it
  // the end's placement) and its attitude.
  double map_sighting_position_sigma_m = 0.01;
  double map_sighting_attitude_sigma_rad = 0.02;
  // The handrail holds the pose while an update was accepted this recently:
  // then a GP jump is rejected, never a relocalisation.
  double handrail_hold_s = 1.0;
};

// nullptr when every field is in range, else the first bad field's name.
const char* validate(const LocalizationConfig& c);

}  // namespace estimator::localization
