#include "sim_hal/sim_gp_localizer.hpp"

#include <algorithm>
#include <cmath>

namespace sim_hal {
namespace {

Eigen::Quaterniond exp_rotation(const Eigen::Vector3d& phi) {
  const double a = phi.norm();
  if (a < 1e-12) return Eigen::Quaterniond(1.0, 0.5 * phi.x(), 0.5 * phi.y(), 0.5 * phi.z());
  return Eigen::Quaterniond(Eigen::AngleAxisd(a, phi / a));
}

}  // namespace

SimGpLocalizer::SimGpLocalizer(const GpLocalizerParams& params, std::uint64_t seed)
    : p_(params), rng_(seed) {
  // Each start direction at right angles to its axis: the direction sweeps
  // a great circle, so over a period it points every way in a plane.
  axis_p_ = random_unit();
  u0_p_ = axis_p_.cross(random_unit()).normalized();
  axis_theta_ = random_unit();
  u0_theta_ = axis_theta_.cross(random_unit()).normalized();
  bias_p_ = p_.bias_m * u0_p_;
  bias_theta_ = p_.bias_rad * u0_theta_;
}

Eigen::Vector3d SimGpLocalizer::gauss3() {
  return {rng_.normal(), rng_.normal(), rng_.normal()};
}

Eigen::Vector3d SimGpLocalizer::random_unit() {
  // A Gaussian vector's direction is uniform on the sphere; a near-zero
  // draw (probability ~1e-9) falls back on an axis.
  const Eigen::Vector3d g = gauss3();
  return g.norm() > 1e-6 ? Eigen::Vector3d(g.normalized()) : Eigen::Vector3d::UnitX();
}

void SimGpLocalizer::drift(std::int64_t t_us) {
  const double angle =
      2.0 * M_PI * 1e-6 * static_cast<double>(t_us - t_start_us_) / p_.drift_period_s;
  bias_p_ = p_.bias_m * (Eigen::AngleAxisd(angle, axis_p_) * u0_p_);
  bias_theta_ = p_.bias_rad * (Eigen::AngleAxisd(angle, axis_theta_) * u0_theta_);
}

std::int64_t SimGpLocalizer::next_period_us() {
  const double period = 1e6 / p_.rate_hz;
  const double f = 1.0 + (2.0 * rng_.uniform() - 1.0) * p_.rate_jitter;
  return static_cast<std::int64_t>(std::llround(period * f));
}

void SimGpLocalizer::on_truth(std::int64_t t_us, const Eigen::Isometry3d& T_world_body) {
  if (!started_) {
    started_ = true;
    t_prev_us_ = t_start_us_ = t_us;
    t_next_capture_us_ = t_us + next_period_us();
    return;
  }
  if (t_us <= t_prev_us_) return;
  drift(t_us);
  t_prev_us_ = t_us;
  if (t_us < t_next_capture_us_) return;
  t_next_capture_us_ += next_period_us();
  if (t_next_capture_us_ <= t_us) t_next_capture_us_ = t_us + next_period_us();  // after a stall
  ++captured_;
  if (rng_.uniform() < p_.dropout_probability) {
    ++dropped_;
    return;
  }
  GpFix f;
  f.capture_time_us = t_us;
  const double latency_s =
      p_.latency_min_s + rng_.uniform() * (p_.latency_max_s - p_.latency_min_s);
  // In capture order: never before the previous fix's delivery.
  f.delivery_time_us =
      std::max(last_delivery_us_, t_us + static_cast<std::int64_t>(std::llround(latency_s * 1e6)));
  last_delivery_us_ = f.delivery_time_us;
  f.seq = ++seq_;
  const Eigen::Vector3d dp = bias_p_ + jump_m_ + p_.white_m * gauss3();
  const Eigen::Vector3d dtheta = bias_theta_ + p_.white_rad * gauss3();
  f.T_world_body.linear() = (exp_rotation(dtheta) * Eigen::Quaterniond(T_world_body.linear()))
                                .normalized()
                                .toRotationMatrix();
  f.T_world_body.translation() = T_world_body.translation() + dp;
  f.cov.setZero();
  f.cov.diagonal() << Eigen::Vector3d::Constant(p_.sigma_m * p_.sigma_m),
      Eigen::Vector3d::Constant(p_.sigma_rad * p_.sigma_rad);
  f.error_p_m = dp;
  f.error_angle_rad = dtheta.norm();
  if (count_ == kMaxPending) {
    // Full (a consumer that stopped polling): the oldest goes.
    head_ = (head_ + 1) % kMaxPending;
    --count_;
    ++overflowed_;
  }
  pending_[static_cast<std::size_t>((head_ + count_) % kMaxPending)] = f;
  ++count_;
}

bool SimGpLocalizer::poll(std::int64_t t_us, GpFix* out) {
  if (count_ == 0) return false;
  const GpFix& f = pending_[static_cast<std::size_t>(head_)];
  if (f.delivery_time_us > t_us) return false;
  *out = f;
  head_ = (head_ + 1) % kMaxPending;
  --count_;
  return true;
}

}  // namespace sim_hal
