#pragma once
// Rotation helpers for the localization filter: skew matrices and the
// quaternion exponential and logarithm, exact at small angles (no division
// by an angle that can be zero).
#include <Eigen/Core>
#include <Eigen/Geometry>

namespace estimator::localization {

// [v x]: skew(v) * w == v.cross(w).
Eigen::Matrix3d skew(const Eigen::Vector3d& v);

// The unit quaternion of the rotation vector phi (axis times angle, rad).
Eigen::Quaterniond quat_exp(const Eigen::Vector3d& phi);

// The rotation vector of a unit quaternion, angle in [0, pi] (the sign of q
// does not matter).
Eigen::Vector3d quat_log(const Eigen::Quaterniond& q);

}  // namespace estimator::localization
