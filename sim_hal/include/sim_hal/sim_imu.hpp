#pragma once
// A simulated IMU (Astrobee's is sampled at 62.5 Hz): it is told the body's
// true pose at every physics tick and returns the samples that fell due
// since the last one. Each sample is what a strapdown IMU with integrating
// outputs reports: the mean angular rate and the mean specific force (no
// gravity: the ISS is in free fall) over the interval since the previous
// sample, in the body frame, so a filter integrating the samples follows the
// simulated motion exactly; then the sensor's errors:
//   white noise       density * sqrt(rate) per sample (angle and velocity
//                     random walk);
//   bias random walk  each bias moves by rw * sqrt(dt) per sample from a
//                     seeded initial bias;
//   saturation        each axis clipped to the sensor's range;
//   sample jitter     each sample's time is the nominal one plus a uniform
//                     jitter (the sample carries its true time).
// The motion between two ticks is taken as the simulator makes it: constant
// linear and angular velocity (SimFlyer integrates that way), so a sample
// between two ticks sees the pose interpolated at its time. Seeded: one seed,
// one sequence. Pure logic, time passed in; no allocation after construction.
#include <Eigen/Geometry>
#include <cstdint>

#include "sim_hal/sim_random.hpp"

namespace sim_hal {

struct ImuParams {
  double rate_hz = 62.5;
  double jitter_us = 500.0;  // each sample's time: nominal +- this (uniform)
  // Noise densities and bias random walks (what the filter's configuration
  // assumes, as an Epson G362-class IMU, less its margin).
  double gyro_noise_radps_rthz = 5e-5;
  double accel_noise_mps2_rthz = 1e-3;
  double gyro_bias_rw_radps2_rthz = 5e-7;
  double accel_bias_rw_mps3_rthz = 5e-5;
  // Initial biases: each axis uniform in +- these.
  double gyro_bias0_radps = 0.002;
  double accel_bias0_mps2 = 0.01;
  // The sensor's range per axis.
  double max_rate_radps = 5.0;
  double max_accel_mps2 = 20.0;
};

struct ImuReading {
  std::int64_t t_us = 0;
  std::uint64_t seq = 0;
  Eigen::Vector3d omega_body_radps = Eigen::Vector3d::Zero();
  Eigen::Vector3d a_body_mps2 = Eigen::Vector3d::Zero();
  bool saturated = false;  // an axis was clipped
};

class SimImu {
 public:
  // At most this many samples from one tick: a tick later than this many
  // sample periods (a stalled host) drops the rest, which the filter sees
  // as a gap, as it would see a stalled IMU driver.
  static constexpr int kMaxPerTick = 16;

  SimImu(const ImuParams& params, std::uint64_t seed);

  // The body's true pose at t_us (ticks in time order). Writes the samples
  // due in (previous tick, t_us] to out[0..n) and returns n. The first
  // tick only starts the clock.
  int on_truth(std::int64_t t_us, const Eigen::Isometry3d& T_world_body,
               ImuReading out[kMaxPerTick]);

  const Eigen::Vector3d& gyro_bias_radps() const { return gyro_bias_; }
  const Eigen::Vector3d& accel_bias_mps2() const { return accel_bias_; }
  std::uint64_t samples() const { return seq_; }
  std::uint64_t dropped() const { return dropped_; }
  const ImuParams& params() const { return p_; }

 private:
  Eigen::Vector3d gauss3();
  double period_us() const { return 1e6 / p_.rate_hz; }
  std::int64_t next_sample_time();
  // The pose at t in (t_prev_, t_cur], moving at the tick's velocities.
  void pose_at(std::int64_t t_us, Eigen::Vector3d* p, Eigen::Quaterniond* q) const;

  ImuParams p_;
  SimRandom rng_;
  Eigen::Vector3d gyro_bias_, accel_bias_;
  bool started_ = false;
  std::int64_t t_prev_us_ = 0;
  Eigen::Vector3d p_prev_ = Eigen::Vector3d::Zero();
  Eigen::Quaterniond q_prev_ = Eigen::Quaterniond::Identity();
  // The current tick interval's velocities (world frame).
  Eigen::Vector3d v_world_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d w_world_ = Eigen::Vector3d::Zero();
  // The previous sample: its time, pose and the world velocity there.
  std::int64_t t_last_us_ = 0;
  Eigen::Quaterniond q_last_ = Eigen::Quaterniond::Identity();
  Eigen::Vector3d v_last_ = Eigen::Vector3d::Zero();
  std::int64_t k_next_ = 1;     // index of the next nominal sample
  std::int64_t t0_us_ = 0;      // nominal sample k is at t0 + k * period
  std::int64_t t_next_us_ = 0;  // the next sample's time, jitter included
  std::uint64_t seq_ = 0, dropped_ = 0;
};

}  // namespace sim_hal
