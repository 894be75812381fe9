#include "estimator/localization/so3.hpp"

#include <cmath>

namespace estimator::localization {

Eigen::Matrix3d skew(const Eigen::Vector3d& v) {
  Eigen::Matrix3d m;
  m << 0.0, -v.z(), v.y(), v.z(), 0.0, -v.x(), -v.y(), v.x(), 0.0;
  return m;
}

Eigen::Quaterniond quat_exp(const Eigen::Vector3d& phi) {
  const double angle = phi.norm();
  const double half = 0.5 * angle;
  // sin(half) / angle, by its series below 1e-4 rad where the quotient
  // loses digits (and is 0 / 0 at zero).
  const double k = angle < 1e-4 ? 0.5 - angle * angle / 48.0 : std::sin(half) / angle;
  Eigen::Quaterniond q(std::cos(half), k * phi.x(), k * phi.y(), k * phi.z());
  q.normalize();
  return q;
}

Eigen::Vector3d quat_log(const Eigen::Quaterniond& q_in) {
  // The shorter way round: w >= 0 keeps the angle in [0, pi].
  const Eigen::Quaterniond q = q_in.w() < 0.0 ? Eigen::Quaterniond(-q_in.coeffs()) : q_in;
  const Eigen::Vector3d v = q.vec();
  const double s = v.norm();
  if (s < 1e-8) return 2.0 * v;  // angle ~ 2 s, error O(s^3)
  const double angle = 2.0 * std::atan2(s, q.w());
  return (angle / s) * v;
}

}  // namespace estimator::localization
