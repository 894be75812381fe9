#include "sim_hal/flyer.hpp"

#include <cmath>

namespace sim_hal {
namespace {

// Moves `v` toward `target` at most `max_step`.
Eigen::Vector3d limited_step(const Eigen::Vector3d& v, const Eigen::Vector3d& target,
                             double max_step) {
  const Eigen::Vector3d d = target - v;
  const double n = d.norm();
  return n <= max_step ? target : Eigen::Vector3d(v + d * (max_step / n));
}

}  // namespace

SimFlyer::SimFlyer(const Eigen::Isometry3d& T_world_body, const FlyerParams& params,
                   std::uint64_t seed)
    : p_(params), T_world_body_(T_world_body), rng_(seed) {}

Eigen::Vector3d SimFlyer::gauss3() {
  return {rng_.normal(), rng_.normal(), rng_.normal()};
}

void SimFlyer::step(double dt_s, const Eigen::Vector3d& v_cmd, const Eigen::Vector3d& w_cmd) {
  if (!(dt_s > 0.0)) return;
  // Ornstein-Uhlenbeck disturbances with stationary deviation as set.
  const double a = std::exp(-dt_s / p_.disturbance_tau_s);
  const double b = std::sqrt(1.0 - a * a);
  push_ = a * push_ + b * p_.disturbance_mps2 * gauss3();
  twist_ = a * twist_ + b * p_.angular_disturbance_rps2 * gauss3();
  // The controller: first order toward the command, acceleration limited.
  const double k = 1.0 - std::exp(-dt_s / p_.velocity_tau_s);
  v_ = limited_step(v_, v_ + k * (v_cmd - v_), p_.max_accel_mps2 * dt_s) + push_ * dt_s;
  w_ = limited_step(w_, w_ + k * (w_cmd - w_), p_.max_angular_accel_rps2 * dt_s) + twist_ * dt_s;
  T_world_body_.translation() += v_ * dt_s;
  const double angle = w_.norm() * dt_s;
  if (angle > 0.0) {
    T_world_body_.linear() =
        (Eigen::AngleAxisd(angle, w_.normalized()) * T_world_body_.linear()).eval();
  }
  // Keep the rotation orthonormal over long runs.
  const Eigen::Quaterniond q(T_world_body_.linear());
  T_world_body_.linear() = q.normalized().toRotationMatrix();
}

void SimFlyer::hold_at(const Eigen::Isometry3d& T_world_body) {
  T_world_body_ = T_world_body;
  v_.setZero();
  w_.setZero();
}

}  // namespace sim_hal
