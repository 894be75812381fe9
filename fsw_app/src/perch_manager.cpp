#include "fsw_app/perch_manager.hpp"

#include <algorithm>
#include <chrono>

#include "fsw_app/msg_convert.hpp"

namespace fsw_app {

void ApproachController::on_estimate(const hrp::handrail_estimate_t& e) {
  if (e.state == hrp::handrail_estimate_t::STATE_NH || e.deadline_missed) return;
  handrail_seen_us_ = std::max(handrail_seen_us_, e.capture_utime);
  if (!e.target_in_world) return;
  T_world_target_ = from_msg(e.T_world_target);
  T_world_handrail_ = from_msg(e.T_world_handrail);
  have_target_ = true;
}

void ApproachController::servo_to(const Eigen::Isometry3d& T_world_body,
                                  const Eigen::Isometry3d& goal, ApproachOutput* out) const {
  Eigen::Vector3d v = cfg_.gain_per_s * (goal.translation() - T_world_body.translation());
  if (v.norm() > cfg_.max_speed_mps) v *= cfg_.max_speed_mps / v.norm();
  const Eigen::AngleAxisd err(goal.linear() * T_world_body.linear().transpose());
  Eigen::Vector3d w = cfg_.gain_per_s * err.angle() * err.axis();
  if (w.norm() > cfg_.max_rate_rps) w *= cfg_.max_rate_rps / w.norm();
  for (int k = 0; k < 3; ++k) {
    out->velocity.velocity_mps[k] = v[k];
    out->velocity.angular_velocity_rps[k] = w[k];
  }
  out->velocity.hold = false;
}

ApproachOutput ApproachController::step(std::int64_t now_us, const hrp::robot_pose_t* pose,
                                        std::int8_t arm_state) {
  using A = hrp::arm_state_t;
  ApproachOutput out;
  out.velocity.utime = out.status.utime = now_us;
  out.velocity.hold = true;
  out.status.handrail_seen_utime = handrail_seen_us_;
  if (!pose || !have_target_) {
    settled_ = 0;
    return out;
  }
  const Eigen::Isometry3d T_world_body = from_msg(pose->T_world_body);
  const Eigen::Vector3d normal = T_world_handrail_.linear().col(0);
  const Eigen::Vector3d to_target = T_world_target_.translation() - T_world_body.translation();
  const double angle =
      Eigen::AngleAxisd(T_world_target_.linear() * T_world_body.linear().transpose()).angle();
  out.status.position_error_m = to_target.norm();
  out.status.angle_error_rad = angle;
  // How far out from the bar the body is, along the wall normal.
  const double out_m = normal.dot(T_world_body.translation() - T_world_handrail_.translation());

  if (arm_state == A::DEPLOYING || arm_state == A::CALIBRATING || arm_state == A::OPENING) {
    Eigen::Isometry3d goal = T_world_target_;
    goal.translation() += cfg_.standoff_m * normal;
    servo_to(T_world_body, goal, &out);
  } else if (arm_state == A::GRIPPER_OPEN) {
    // In toward the wall only as the robot lines up across it.
    const Eigen::Vector3d lateral = to_target - normal.dot(to_target) * normal;
    const double standoff = std::clamp(4.0 * lateral.norm() + 0.5 * angle, 0.0, cfg_.standoff_m);
    Eigen::Isometry3d goal = T_world_target_;
    goal.translation() += standoff * normal;
    servo_to(T_world_body, goal, &out);
    const bool within = out.status.position_error_m <= cfg_.position_tolerance_m &&
                        angle <= cfg_.angle_tolerance_rad;
    settled_ = within ? settled_ + 1 : 0;
    out.status.at_target = settled_ >= cfg_.settle_cycles;
  } else {
    settled_ = 0;
  }
  if (arm_state == A::BACKING_OFF || arm_state == A::STOWING) {
    if (!backing_off_) {
      backing_off_ = true;
      back_off_start_m_ = out_m;
    }
    Eigen::Isometry3d goal = T_world_body;
    goal.translation() =
        T_world_handrail_.translation() + (back_off_start_m_ + cfg_.back_off_m) * normal +
        (T_world_body.translation() - T_world_handrail_.translation() - out_m * normal);
    servo_to(T_world_body, goal, &out);
    out.status.backed_off = out_m >= back_off_start_m_ + 0.9 * cfg_.back_off_m;
  } else {
    backing_off_ = false;
  }
  return out;
}

PerchManager::PerchManager(LcmHub& hub, const ApproachConfig& cfg, const hal::Clock& clock,
                           double rate_hz)
    : hub_(hub),
      clock_(clock),
      controller_(cfg),
      period_us_(static_cast<std::int64_t>(1e6 / rate_hz)),
      velocity_pub_(hub, channel::kBodyVelocityCommand),
      status_pub_(hub, channel::kApproachStatus) {
  hub_.subscribe(channel::kHandrailEstimate, &estimate_box_);
  hub_.subscribe(channel::kRobotPose, &pose_box_);
  hub_.subscribe(channel::kArmState, &arm_box_);
  arm_.state_name.reserve(32);
  arm_.fault_name.reserve(32);
  arm_.fault_text.reserve(160);
  arm_.last_reject_name.reserve(32);
}

PerchManager::~PerchManager() {
  stop();
}

void PerchManager::start() {
  if (running_.exchange(true)) return;
  thread_ = std::thread([this] {
    auto next = std::chrono::steady_clock::now();
    while (running_.load()) {
      cycle();
      next += std::chrono::microseconds(period_us_);
      const auto now = std::chrono::steady_clock::now();
      if (next < now) next = now;
      std::this_thread::sleep_until(next);
    }
  });
}

void PerchManager::stop() {
  if (!running_.exchange(false)) return;
  if (thread_.joinable()) thread_.join();
}

void PerchManager::cycle() {
  const std::uint64_t seq = estimate_box_.read(&estimate_);
  if (seq != estimate_seen_) {
    estimate_seen_ = seq;
    controller_.on_estimate(estimate_);
  }
  const bool have_pose = pose_box_.read(&pose_) != 0;
  const std::int8_t arm_state = arm_box_.read(&arm_) != 0 ? arm_.state : hrp::arm_state_t::INIT;
  const ApproachOutput out =
      controller_.step(clock_.now_us(), have_pose ? &pose_ : nullptr, arm_state);
  velocity_pub_.publish(out.velocity);
  status_pub_.publish(out.status);
}

}  // namespace fsw_app
