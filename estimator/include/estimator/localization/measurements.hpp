#pragma once
// The filter's inputs: IMU samples, general-purpose (GP) localizer poses and
// handrail measurements. Times are microseconds on the robot's clock; every
// measurement carries its capture time, not its arrival time.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <cstdint>

#include "estimator/types.hpp"

namespace estimator::localization {

// One IMU sample, in the body frame (a sample in the IMU's own frame is
// rotated into the body frame by the caller; the lever arm from the body
// origin is neglected: at Astrobee's rates, under 0.5 rad/s, the centripetal
// term at 0.1 m is below 0.025 m/s^2 and looks to the filter like a slowly
// varying accelerometer bias).
struct ImuSample {
  std::int64_t t_us = 0;
  Eigen::Vector3d omega_body_radps = Eigen::Vector3d::Zero();  // angular rate
  Eigen::Vector3d a_body_mps2 = Eigen::Vector3d::Zero();       // specific force
};

// Covariance of a pose: [position (m), attitude (rad)], the attitude error
// in the world frame as the filter's (state.hpp).
using PoseCovariance = Eigen::Matrix<double, 6, 6>;

// A pose from the general-purpose localizer (sparse map, ~1 to 2 Hz,
// 100 to 300 ms late). The measurement model: p = p_true + n_p,
// q = Exp(n_theta) q_true, [n_p, n_theta] ~ N(0, cov).
struct GpPose {
  std::int64_t capture_time_us = 0;
  Eigen::Vector3d p_world_body_m = Eigen::Vector3d::Zero();
  Eigen::Quaterniond q_world_body = Eigen::Quaterniond::Identity();
  PoseCovariance cov = PoseCovariance::Identity();
};

// Where a depth feature lies: on the bar, or on the wall behind it.
enum class FeatureKind : std::uint8_t { kBar, kWall };

// One depth feature (the paper's feature j of camera frame i).
struct HandrailFeature {
  Eigen::Vector3d p_cam_m = Eigen::Vector3d::Zero();       // z_i^(j), measured (eq. 6)
  Eigen::Vector3d p_handrail_m = Eigen::Vector3d::Zero();  // ^H p_j (eq. 8, second line)
  FeatureKind kind = FeatureKind::kBar;
};

// As many features as the flown detector published (40 on the bar, 20 on the
// wall), and a few more.
constexpr int kMaxInputFeatures = 64;

// One handrail detection as a measurement.
struct HandrailMeasurement {
  std::int64_t capture_time_us = 0;
  HandrailState state = HandrailState::kNoHandrail;  // BE, OE or NE are usable
  // The detected handrail frame (eq. 5): x = wall normal toward the camera,
  // z = along the bar. With an end seen (BE, OE) its origin is the bar's
  // centre; with none (NE) the origin's position along the bar is arbitrary.
  Eigen::Isometry3d T_cam_handrail = Eigen::Isometry3d::Identity();
  std::array<HandrailFeature, kMaxInputFeatures> features{};
  int num_features = 0;
};

// Fills features [0, n) of m from camera-frame points, with ^H p_j from the
// detected pose (the paper's eq. 8, second line: ^H p_j = ^H p_C + C z_j).
// At most kMaxInputFeatures are taken; returns how many were.
int add_features(const Eigen::Vector3d* p_cam_m, int n, FeatureKind kind, HandrailMeasurement* m);

}  // namespace estimator::localization
