#pragma once
// The filter's state: the nominal state (position, velocity and attitude of
// the body in the world frame, gyro and accelerometer biases, and the
// handrail map's world pose) and its 21-dimensional error state, with the
// covariance of that error.
//
// Error state, in this order (kPos ... kMapAtt are the offsets):
//   dp      world frame, m        p_true = p + dp
//   dv      world frame, m/s      v_true = v + dv
//   dtheta  world frame, rad      q_true = Exp(dtheta) * q  (a rotation
//                                 about world axes, applied after q)
//   dbg     body frame, rad/s     bg_true = bg + dbg
//   dba     body frame, m/s^2     ba_true = ba + dba
//   dp_map  world frame, m        the handrail's origin, as dp
//   dth_map world frame, rad      the handrail's attitude, as dtheta
// The attitude error lives in the world frame (a choice of the design); the
// paper's eq. 10 writes its Jacobian for an error in the camera frame, which
// is R_cam_world times ours (handrail_update.hpp does that mapping).
//
// Why the map is in the state: a handrail placed from the robot's own pose
// carries that pose's world error, correlated with the robot's. Held fixed
// with no uncertainty, every update against it would shrink the robot's
// world covariance below what is known, and the filter would claim
// centimetres it does not have. As states, the map keeps the uncertainty it
// was built with (map_state.hpp), the handrail updates constrain the robot
// relative to it, and only the GP (or a survey) places both in the world.
// The map never moves on its own: identity in the transition, no process
// noise. While there is no map the block holds a placeholder, uncorrelated
// and observed by nothing.
//
// Doubles throughout: the covariance spans 1e-10 (gyro bias, rad^2/s^2) to
// 1e0 (position before a fix), beyond a float's 7 digits, and the
// BeagleBone's Cortex-A8 does doubles in its VFP (NEON, which has no
// doubles, is not needed for 21 x 21 matrices).
#include <Eigen/Core>
#include <Eigen/Geometry>

namespace estimator::localization {

constexpr int kErrorDim = 21;
constexpr int kPos = 0;
constexpr int kVel = 3;
constexpr int kAtt = 6;
constexpr int kGyroBias = 9;
constexpr int kAccelBias = 12;
constexpr int kMapPos = 15;
constexpr int kMapAtt = 18;

using ErrorVector = Eigen::Matrix<double, kErrorDim, 1>;
using Covariance = Eigen::Matrix<double, kErrorDim, kErrorDim>;

struct NominalState {
  Eigen::Vector3d p_world_body_m = Eigen::Vector3d::Zero();
  Eigen::Vector3d v_world_body_mps = Eigen::Vector3d::Zero();
  Eigen::Quaterniond q_world_body = Eigen::Quaterniond::Identity();
  Eigen::Vector3d gyro_bias_radps = Eigen::Vector3d::Zero();  // body frame
  Eigen::Vector3d accel_bias_mps2 = Eigen::Vector3d::Zero();  // body frame
  // The handrail map's pose (meaningful while the filter has a map).
  Eigen::Vector3d p_world_handrail_m = Eigen::Vector3d::Zero();
  Eigen::Quaterniond q_world_handrail = Eigen::Quaterniond::Identity();
};

bool is_finite(const NominalState& x);

// Folds an estimated error into the nominal state (p += dp, v += dv,
// q = Exp(dtheta) q, biases += ..., the map likewise) and resets the
// covariance to the new error's: P = G P G^T with G = I except
// G_theta = I + [dtheta / 2 x] for each attitude (the reset Jacobian of a
// world-frame attitude error).
void inject(const ErrorVector& dx, NominalState* x, Covariance* P);

}  // namespace estimator::localization
