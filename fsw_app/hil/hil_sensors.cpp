#include "hil_sensors.hpp"

#include <algorithm>
#include <cmath>

#include <Eigen/Cholesky>

#include "fsw_app/msg_convert.hpp"

namespace fsw_app {
namespace {

constexpr double kRadToDeg = 180.0 / M_PI;

// Distinct streams of one run's seed for the two sensors.
constexpr std::uint64_t kImuStream = 0x1a2b;
constexpr std::uint64_t kGpStream = 0x3c4d;

}  // namespace

HilSensorParams hil_sensor_params(double gp_bias_m, double gp_bias_deg) {
  HilSensorParams p;
  p.gp.bias_m = gp_bias_m;
  p.gp.bias_rad = gp_bias_deg / kRadToDeg;
  // The bias is a vector of that length: per axis about 0.6 of it (rms),
  // what the localizer would claim from its own residuals.
  p.gp.sigma_m = std::max(0.02, 0.6 * gp_bias_m);
  p.gp.sigma_rad = std::max(0.5 / kRadToDeg, 0.6 * p.gp.bias_rad);
  return p;
}

HilSensors::HilSensors(LcmHub& hub, const HilSensorParams& params, std::uint64_t seed)
    : hub_(hub),
      imu_(params.imu, sim_hal::mix_seed(seed, 0, kImuStream)),
      gp_(params.gp, sim_hal::mix_seed(seed, 0, kGpStream)),
      imu_pub_(hub, channel::kImuSample),
      gp_pub_(hub, channel::kGpPose),
      truth_pub_(hub, channel::kTruthPose) {
  // The simulator's scorer reads the robot's pose like any listener; it is
  // not a robot-side task.
  hub_.subscribe(channel::kRobotPose, &estimate_box_);
  truth_msg_.source = hrp::robot_pose_t::SOURCE_TRUTH;
}

void HilSensors::jump_gp(const Eigen::Vector3d& dp_world_m) {
  gp_.jump_by(dp_world_m);
}

void HilSensors::begin_scoring() {
  std::lock_guard<std::mutex> lock(mutex_);
  scoring_ = true;
}

void HilSensors::mark_grasp() {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!scoring_ || score_.at_grasp) return;
  score_.at_grasp = true;
  score_.filter_grasp_m = latest_filter_m_;
  score_.filter_grasp_deg = latest_filter_deg_;
  score_.gp_grasp_m = latest_gp_m_;
  score_.gp_grasp_deg = latest_gp_deg_;
  scoring_ = false;
}

LocalizationScore HilSensors::score() const {
  std::lock_guard<std::mutex> lock(mutex_);
  LocalizationScore s = score_;
  s.imu_samples = imu_.samples();
  s.gp_fixes = gp_.captured() - gp_.dropped();
  s.gp_dropped = gp_.dropped();
  return s;
}

bool HilSensors::truth_at(std::int64_t t_us, Eigen::Isometry3d* T) const {
  if (truth_count_ == 0) return false;
  int best = -1;
  std::int64_t best_dt = INT64_MAX;
  for (int k = 0; k < truth_count_; ++k) {
    const TruthSample& s = truth_[static_cast<std::size_t>(k)];
    const std::int64_t dt = s.t_us > t_us ? s.t_us - t_us : t_us - s.t_us;
    if (dt < best_dt) {
      best_dt = dt;
      best = k;
    }
  }
  if (best_dt > 20000) return false;  // not within the ring's ticks
  // Between ticks the flyer moves at constant velocity; at the nearest tick
  // the error is under 5 ms of motion (0.25 mm at 5 cm/s).
  *T = truth_[static_cast<std::size_t>(best)].T;
  return true;
}

void HilSensors::score_filter() {
  const std::uint64_t seq = estimate_box_.read(&estimate_);
  if (seq == estimate_seen_) return;
  estimate_seen_ = seq;
  std::lock_guard<std::mutex> lock(mutex_);
  if (estimate_.source != hrp::robot_pose_t::SOURCE_FILTER) {
    ++score_.non_filter_poses;
    return;
  }
  ++score_.filter_poses;
  Eigen::Isometry3d T_true;
  if (!truth_at(estimate_.utime, &T_true)) return;
  const Eigen::Isometry3d T_est = from_msg(estimate_.T_world_body);
  latest_filter_m_ = (T_est.translation() - T_true.translation()).norm();
  latest_filter_deg_ =
      Eigen::AngleAxisd(T_est.linear().transpose() * T_true.linear()).angle() * kRadToDeg;
  if (!scoring_) return;
  score_.filter_approach.add(latest_filter_m_, latest_filter_deg_);
  // The filter's claim against its error: position and attitude (world
  // axes, R_est = exp(dtheta) R_true) each against its 3 x 3 block.
  Eigen::Matrix<double, 6, 6> P;
  for (int r = 0; r < 6; ++r)
    for (int c = 0; c < 6; ++c) P(r, c) = estimate_.pose_covariance[r][c];
  const Eigen::Vector3d e_p = T_est.translation() - T_true.translation();
  const Eigen::AngleAxisd e_q(T_est.linear() * T_true.linear().transpose());
  const Eigen::Vector3d e_a = e_q.angle() * e_q.axis();
  const Eigen::LDLT<Eigen::Matrix3d> Pp(P.topLeftCorner<3, 3>()), Pa(P.bottomRightCorner<3, 3>());
  if (Pp.info() != Eigen::Success || Pa.info() != Eigen::Success || !Pp.isPositive() ||
      !Pa.isPositive() || !(P.topLeftCorner<3, 3>().diagonal().minCoeff() > 0.0) ||
      !(P.bottomRightCorner<3, 3>().diagonal().minCoeff() > 0.0)) {
    return;
  }
  score_.filter_nees_approach.add(e_p.dot(Pp.solve(e_p)), e_a.dot(Pa.solve(e_a)));
}

void HilSensors::on_tick(std::int64_t now_us, const Eigen::Isometry3d& T_world_body,
                         const Eigen::Vector3d& v_world_mps, const Eigen::Vector3d& w_world_rps,
                         bool publish_truth) {
  TruthSample& slot = truth_[static_cast<std::size_t>(truth_next_)];
  slot.t_us = now_us;
  slot.T = T_world_body;
  truth_next_ = (truth_next_ + 1) % kTruthRing;
  truth_count_ = std::min(truth_count_ + 1, kTruthRing);

  const int n = imu_.on_truth(now_us, T_world_body, readings_.data());
  for (int k = 0; k < n && now_us >= imu_silent_until_us_; ++k) {
    const sim_hal::ImuReading& r = readings_[static_cast<std::size_t>(k)];
    imu_msg_.utime = r.t_us;
    imu_msg_.seq = static_cast<std::int64_t>(r.seq);
    for (int i = 0; i < 3; ++i) {
      imu_msg_.omega_body_radps[i] = r.omega_body_radps[i];
      imu_msg_.a_body_mps2[i] = r.a_body_mps2[i];
    }
    imu_msg_.saturated = r.saturated;
    imu_pub_.publish(imu_msg_);
  }
  gp_.on_truth(now_us, T_world_body);
  sim_hal::GpFix fix;
  while (gp_.poll(now_us, &fix)) {
    gp_msg_.utime = now_us;
    gp_msg_.capture_utime = fix.capture_time_us;
    gp_msg_.seq = static_cast<std::int64_t>(fix.seq);
    to_msg(fix.T_world_body, &gp_msg_.T_world_body);
    for (int r = 0; r < 6; ++r)
      for (int c = 0; c < 6; ++c) gp_msg_.covariance[r][c] = fix.cov(r, c);
    gp_pub_.publish(gp_msg_);
    std::lock_guard<std::mutex> lock(mutex_);
    latest_gp_m_ = fix.error_p_m.norm();
    latest_gp_deg_ = fix.error_angle_rad * kRadToDeg;
    if (scoring_) score_.gp_approach.add(latest_gp_m_, latest_gp_deg_);
  }
  if (publish_truth) {
    truth_msg_.utime = now_us;
    to_msg(T_world_body, &truth_msg_.T_world_body);
    for (int k = 0; k < 3; ++k) {
      truth_msg_.velocity_mps[k] = v_world_mps[k];
      truth_msg_.angular_velocity_rps[k] = w_world_rps[k];
    }
    truth_pub_.publish(truth_msg_);
  }
  score_filter();
}

}  // namespace fsw_app
