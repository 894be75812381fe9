#pragma once
// A simulated general-purpose (GP) localizer, the robot's sparse-map and
// visual-odometry pose source: told the body's true pose at every physics
// tick, it captures a pose about every 1 / rate_hz seconds and delivers it
// 100 to 300 ms later, as Astrobee's does. Its errors:
//   bias      a slowly drifting offset of fixed size: bias_m in position and
//             bias_rad in attitude, each along a direction that turns
//             steadily about a seeded random axis, once per drift_period_s
//             (smooth, unlike a random walk, whose steps between two fixes
//             would look like white noise), so "5 cm and 2 deg off" stays
//             that far off while the direction of the error changes;
//   white     Gaussian noise per pose (white_m, white_rad per axis);
//   dropouts  each capture lost with probability dropout_probability;
//   latency   uniform in [latency_min_s, latency_max_s], delivered in
//             capture order (a later capture never overtakes);
//   jumps     jump_by() adds a step to the position (a relocalisation).
// It reports the covariance it claims (sigma_m, sigma_rad per axis), not
// its true error. The attitude error is applied as the filter models it:
// q = Exp(n_theta) q_true (world frame). Seeded, pure logic, time passed in;
// fixed memory.
#include <Eigen/Geometry>
#include <array>
#include <cstdint>

#include "sim_hal/sim_random.hpp"

namespace sim_hal {

struct GpLocalizerParams {
  double rate_hz = 1.5;
  double rate_jitter = 0.2;  // each period: nominal * (1 +- this), uniform
  double latency_min_s = 0.10, latency_max_s = 0.30;
  double bias_m = 0.03, bias_rad = 0.0175;  // about 3 cm and 1 deg
  double drift_period_s = 240.0;
  double white_m = 0.005, white_rad = 0.003;
  double dropout_probability = 0.05;
  double sigma_m = 0.04, sigma_rad = 0.03;  // what it claims, per axis
};

struct GpFix {
  std::int64_t capture_time_us = 0;
  std::int64_t delivery_time_us = 0;
  std::uint64_t seq = 0;
  Eigen::Isometry3d T_world_body = Eigen::Isometry3d::Identity();
  Eigen::Matrix<double, 6, 6> cov = Eigen::Matrix<double, 6, 6>::Identity();  // [p, theta]
  // For scoring only (never sent to the robot): the error of this fix.
  Eigen::Vector3d error_p_m = Eigen::Vector3d::Zero();
  double error_angle_rad = 0.0;
};

class SimGpLocalizer {
 public:
  static constexpr int kMaxPending = 8;  // 0.3 s of latency at up to 20 Hz

  SimGpLocalizer(const GpLocalizerParams& params, std::uint64_t seed);

  // The body's true pose at t_us (ticks in time order): captures a fix when
  // one falls due.
  void on_truth(std::int64_t t_us, const Eigen::Isometry3d& T_world_body);
  // The next fix delivered by t_us, oldest first; false when none is due.
  bool poll(std::int64_t t_us, GpFix* out);
  // From now on every fix is offset by this much more (world frame).
  void jump_by(const Eigen::Vector3d& dp_world_m) { jump_m_ += dp_world_m; }

  // The bias now (position, world frame; rotation vector, world frame).
  const Eigen::Vector3d& bias_p_m() const { return bias_p_; }
  const Eigen::Vector3d& bias_theta_rad() const { return bias_theta_; }
  std::uint64_t captured() const { return captured_; }
  std::uint64_t dropped() const { return dropped_; }
  std::uint64_t overflowed() const { return overflowed_; }

 private:
  Eigen::Vector3d gauss3();
  Eigen::Vector3d random_unit();
  void drift(std::int64_t t_us);
  std::int64_t next_period_us();

  GpLocalizerParams p_;
  SimRandom rng_;
  // Each bias direction: u0 turned about axis by 2 pi t / drift_period_s.
  Eigen::Vector3d axis_p_, u0_p_, axis_theta_, u0_theta_;
  std::int64_t t_start_us_ = 0;
  Eigen::Vector3d bias_p_ = Eigen::Vector3d::Zero(), bias_theta_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d jump_m_ = Eigen::Vector3d::Zero();
  bool started_ = false;
  std::int64_t t_prev_us_ = 0, t_next_capture_us_ = 0, last_delivery_us_ = 0;
  std::array<GpFix, kMaxPending> pending_{};
  int head_ = 0, count_ = 0;
  std::uint64_t captured_ = 0, dropped_ = 0, overflowed_ = 0, seq_ = 0;
};

}  // namespace sim_hal
