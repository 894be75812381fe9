#include "sim_hal/sim_imu.hpp"

#include <algorithm>
#include <cmath>

namespace sim_hal {
namespace {

// Rotation vector of a unit quaternion (angle in [0, pi]).
Eigen::Vector3d rotation_vector(Eigen::Quaterniond q) {
  if (q.w() < 0.0) q.coeffs() = -q.coeffs();
  const double s = q.vec().norm();
  if (s < 1e-12) return 2.0 * q.vec();
  return (2.0 * std::atan2(s, q.w()) / s) * q.vec();
}

Eigen::Quaterniond exp_rotation(const Eigen::Vector3d& phi) {
  const double a = phi.norm();
  if (a < 1e-12) return Eigen::Quaterniond(1.0, 0.5 * phi.x(), 0.5 * phi.y(), 0.5 * phi.z());
  return Eigen::Quaterniond(Eigen::AngleAxisd(a, phi / a));
}

// Clips each axis to +-limit; true when any was clipped.
bool clip(Eigen::Vector3d* v, double limit) {
  bool clipped = false;
  for (int k = 0; k < 3; ++k) {
    if (std::fabs((*v)[k]) > limit) {
      (*v)[k] = std::copysign(limit, (*v)[k]);
      clipped = true;
    }
  }
  return clipped;
}

}  // namespace

SimImu::SimImu(const ImuParams& params, std::uint64_t seed) : p_(params), rng_(seed) {
  const auto spread = [this](double half) {
    return Eigen::Vector3d((2.0 * rng_.uniform() - 1.0) * half, (2.0 * rng_.uniform() - 1.0) * half,
                           (2.0 * rng_.uniform() - 1.0) * half);
  };
  gyro_bias_ = spread(p_.gyro_bias0_radps);
  accel_bias_ = spread(p_.accel_bias0_mps2);
}

Eigen::Vector3d SimImu::gauss3() {
  return {rng_.normal(), rng_.normal(), rng_.normal()};
}

std::int64_t SimImu::next_sample_time() {
  const double nominal = static_cast<double>(t0_us_) + static_cast<double>(k_next_) * period_us();
  const double jitter = (2.0 * rng_.uniform() - 1.0) * p_.jitter_us;
  return static_cast<std::int64_t>(std::llround(nominal + jitter));
}

void SimImu::pose_at(std::int64_t t_us, Eigen::Vector3d* p, Eigen::Quaterniond* q) const {
  const double s = 1e-6 * static_cast<double>(t_us - t_prev_us_);
  *p = p_prev_ + v_world_ * s;
  *q = (exp_rotation(w_world_ * s) * q_prev_).normalized();
}

int SimImu::on_truth(std::int64_t t_us, const Eigen::Isometry3d& T_world_body,
                     ImuReading out[kMaxPerTick]) {
  const Eigen::Vector3d p = T_world_body.translation();
  const Eigen::Quaterniond q = Eigen::Quaterniond(T_world_body.linear()).normalized();
  if (!started_) {
    started_ = true;
    t_prev_us_ = t_last_us_ = t0_us_ = t_us;
    p_prev_ = p;
    q_prev_ = q_last_ = q;
    k_next_ = 1;
    t_next_us_ = next_sample_time();
    return 0;
  }
  if (t_us <= t_prev_us_) return 0;
  const double dt_s = 1e-6 * static_cast<double>(t_us - t_prev_us_);
  v_world_ = (p - p_prev_) / dt_s;
  w_world_ = rotation_vector(q * q_prev_.conjugate()) / dt_s;
  // A stall of more than a second: the samples in it are lost whole, and
  // the next one is the first after it (bounds this loop).
  const std::int64_t max_behind_us = static_cast<std::int64_t>(1e6);
  if (t_us - t_next_us_ > max_behind_us) {
    const double missed = std::floor(static_cast<double>(t_us - t_next_us_) / period_us());
    const auto skip = static_cast<std::int64_t>(missed);
    dropped_ += static_cast<std::uint64_t>(skip);
    k_next_ += skip;
    t_next_us_ = next_sample_time();
  }
  int n = 0;
  while (t_next_us_ <= t_us) {
    Eigen::Vector3d p_s;
    Eigen::Quaterniond q_s;
    pose_at(t_next_us_, &p_s, &q_s);
    const double dt_sample_s = 1e-6 * static_cast<double>(t_next_us_ - t_last_us_);
    if (n < kMaxPerTick && dt_sample_s > 0.0) {
      ImuReading& r = out[n++];
      r.t_us = t_next_us_;
      r.seq = ++seq_;
      // The biases walk, then the mean rate and specific force over the
      // interval since the previous sample, in the body frame.
      gyro_bias_ += p_.gyro_bias_rw_radps2_rthz * std::sqrt(dt_sample_s) * gauss3();
      accel_bias_ += p_.accel_bias_rw_mps3_rthz * std::sqrt(dt_sample_s) * gauss3();
      const Eigen::Vector3d omega = rotation_vector(q_last_.conjugate() * q_s) / dt_sample_s;
      const Eigen::Quaterniond q_mid = q_last_.slerp(0.5, q_s);
      const Eigen::Vector3d a = q_mid.conjugate() * ((v_world_ - v_last_) / dt_sample_s);
      const double root_rate = 1.0 / std::sqrt(dt_sample_s);
      r.omega_body_radps = omega + gyro_bias_ + p_.gyro_noise_radps_rthz * root_rate * gauss3();
      r.a_body_mps2 = a + accel_bias_ + p_.accel_noise_mps2_rthz * root_rate * gauss3();
      const bool rate_clipped = clip(&r.omega_body_radps, p_.max_rate_radps);
      const bool accel_clipped = clip(&r.a_body_mps2, p_.max_accel_mps2);
      r.saturated = rate_clipped || accel_clipped;
    } else {
      ++dropped_;
    }
    t_last_us_ = t_next_us_;
    q_last_ = q_s;
    v_last_ = v_world_;
    ++k_next_;
    t_next_us_ = next_sample_time();
  }
  t_prev_us_ = t_us;
  p_prev_ = p;
  q_prev_ = q;
  return n;
}

}  // namespace sim_hal
