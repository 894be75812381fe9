#include "fsw_app/perch_manager.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "fsw_app/msg_convert.hpp"

namespace fsw_app {

const char* to_string(CameraLiveness liveness) {
  switch (liveness) {
    case CameraLiveness::kStreaming:
      return "STREAMING";
    case CameraLiveness::kLate:
      return "LATE";
    case CameraLiveness::kNotSeen:
      return "NOT_SEEN";
  }
  return "UNKNOWN";
}

namespace {

// The states in which the robot flies on the sightings: toward the
// stand-off pose and in to the bar. CLOSING and GRASP_CHECK keep station on
// the pose alone; the back-off flies out along the wall normal.
bool flies_on_sightings(std::int8_t arm_state) {
  using A = hrp::arm_state_t;
  return arm_state == A::DEPLOYING || arm_state == A::CALIBRATING || arm_state == A::OPENING ||
         arm_state == A::GRIPPER_OPEN;
}

}  // namespace

void ApproachController::on_estimate(const hrp::handrail_estimate_t& e) {
  // Any estimate, even "no handrail" or over budget, says a frame came.
  if (frame_seen_us_ >= 0 && e.capture_utime > frame_seen_us_) {
    watch_.longest_frame_gap_us =
        std::max(watch_.longest_frame_gap_us, e.capture_utime - frame_seen_us_);
  }
  frame_seen_us_ = std::max(frame_seen_us_, e.capture_utime);
  if (e.state == hrp::handrail_estimate_t::STATE_NH || e.deadline_missed) return;
  handrail_seen_us_ = std::max(handrail_seen_us_, e.capture_utime);
  if (!e.target_in_world) return;
  T_world_target_ = from_msg(e.T_world_target);
  T_world_handrail_ = from_msg(e.T_world_handrail);
  have_target_ = true;
}

void ApproachController::servo_to(const Eigen::Isometry3d& T_world_body,
                                  const Eigen::Isometry3d& goal, ApproachOutput* out, double dt_s,
                                  const Eigen::Vector3d* approach_axis) {
  // The point that must meet the bar is the grasp point, not the body's
  // origin 0.4 m away: servo it, and turn the body about it.
  const Eigen::Vector3d e = goal * p_body_grasp_ - T_world_body * p_body_grasp_;
  // Integral action takes out slow pushes (air flow); only near the goal,
  // and bounded, so that a long transit does not wind it up.
  if (e.norm() < 0.05) {
    integral_ += e * dt_s;
    const double cap = 0.5 * cfg_.max_speed_mps / std::max(cfg_.integral_gain_per_s2, 1e-6);
    if (integral_.norm() > cap) integral_ *= cap / integral_.norm();
  } else {
    integral_.setZero();
  }
  Eigen::Vector3d v = cfg_.gain_per_s * e + cfg_.integral_gain_per_s2 * integral_;
  if (approach_axis) {
    // Toward the wall only as fast as the robot is lined up across it.
    const Eigen::Vector3d lateral = e - approach_axis->dot(e) * *approach_axis;
    const double lined_up = std::clamp(1.0 - lateral.norm() / 0.03, 0.0, 1.0);
    const double in = approach_axis->dot(v);
    if (in > 0.0) v -= (1.0 - lined_up) * in * *approach_axis;
  }
  // No faster than the robot can stop in the distance left, braking
  // gently: overshooting toward the wall with the gripper open is the
  // failure that matters.
  const double v_max = std::min(cfg_.max_speed_mps, std::sqrt(2.0 * cfg_.brake_mps2 * e.norm()));
  if (v.norm() > v_max) v *= v_max / v.norm();
  const Eigen::AngleAxisd err(goal.linear() * T_world_body.linear().transpose());
  Eigen::Vector3d w = cfg_.gain_per_s * err.angle() * err.axis();
  if (w.norm() > cfg_.max_rate_rps) w *= cfg_.max_rate_rps / w.norm();
  // The body's origin moves so that the grasp point moves at v.
  v -= w.cross(T_world_body.linear() * p_body_grasp_);
  for (int k = 0; k < 3; ++k) {
    out->velocity.velocity_mps[k] = v[k];
    out->velocity.angular_velocity_rps[k] = w[k];
  }
  out->velocity.hold = false;
}

bool ApproachController::pose_usable(std::int64_t now_us, const hrp::robot_pose_t* pose) const {
  if (pose == nullptr) return false;
  if (pose->source != hrp::robot_pose_t::SOURCE_FILTER || pose->lost) return false;
  // A pose dated ahead of this clock was refused on receipt; one this old
  // is where the robot was, not where it is.
  if (now_us - pose->utime > cfg_.pose_max_age_ms * 1000LL) return false;
  // One the filter gives a spread this wide is a guess. The covariance's
  // rows are position then attitude error; its diagonal was checked
  // finite and non-negative on receipt.
  const auto& P = pose->pose_covariance;
  const double position_sigma_m = std::sqrt(P[0][0] + P[1][1] + P[2][2]);
  const double attitude_sigma_rad = std::sqrt(P[3][3] + P[4][4] + P[5][5]);
  return position_sigma_m <= cfg_.pose_max_position_sigma_m &&
         attitude_sigma_rad <= cfg_.pose_max_attitude_sigma_rad;
}

void ApproachController::judge_camera(std::int64_t now_us, std::int64_t dt_us,
                                      hrp::approach_status_t* status) {
  const std::int64_t hold_after_us = cfg_.camera_hold_frames * cfg_.frame_period_us;
  status->frame_seen_utime = frame_seen_us_;
  if (frame_seen_us_ < 0) {
    // None yet (a camera starting): late since the manager's first cycle.
    watch_.liveness = CameraLiveness::kNotSeen;
    status->camera = hrp::approach_status_t::CAMERA_NOT_SEEN;
    status->frame_age_ms = -1;
    if (camera_late_since_us_ < 0) camera_late_since_us_ = now_us;
    status->camera_late_since_utime = camera_late_since_us_;
    return;
  }
  const std::int64_t age_us = std::max<std::int64_t>(0, now_us - frame_seen_us_);
  status->frame_age_ms = static_cast<std::int32_t>(
      std::min<std::int64_t>(age_us / 1000, std::numeric_limits<std::int32_t>::max()));
  if (age_us > hold_after_us) {
    if (watch_.liveness == CameraLiveness::kStreaming) ++watch_.late_spells;
    if (watch_.liveness == CameraLiveness::kLate) watch_.late_us += dt_us;
    watch_.liveness = CameraLiveness::kLate;
    status->camera = hrp::approach_status_t::CAMERA_LATE;
    // Late from the moment the bound passed, not from this cycle: the
    // arm's allowance is measured from the frames, not from the loop.
    if (camera_late_since_us_ < 0) camera_late_since_us_ = frame_seen_us_ + hold_after_us;
  } else {
    watch_.liveness = CameraLiveness::kStreaming;
    status->camera = hrp::approach_status_t::CAMERA_STREAMING;
    camera_late_since_us_ = -1;
  }
  status->camera_late_since_utime = camera_late_since_us_;
}

ApproachOutput ApproachController::step(std::int64_t now_us, const hrp::robot_pose_t* pose,
                                        std::int8_t arm_state) {
  using A = hrp::arm_state_t;
  ApproachOutput out;
  const std::int64_t dt_us = last_step_us_ > 0 ? now_us - last_step_us_ : 0;
  const double dt_s = std::min(0.2, 1e-6 * static_cast<double>(dt_us));
  last_step_us_ = now_us;
  out.velocity.utime = out.status.utime = now_us;
  out.velocity.hold = true;
  out.status.handrail_seen_utime = handrail_seen_us_;
  // No pose to fly on: hold still, and say since when (the arm aborts the
  // perch if it lasts).
  out.status.pose_usable = pose_usable(now_us, pose);
  if (out.status.pose_usable) {
    pose_unusable_since_us_ = -1;
  } else if (pose_unusable_since_us_ < 0) {
    pose_unusable_since_us_ = now_us;
  }
  out.status.pose_unusable_since_utime = pose_unusable_since_us_;
  // No fresh frame: the target is where the bar was last seen, so the
  // robot holds rather than fly in on it (the arm aborts if it lasts).
  judge_camera(now_us, dt_us, &out.status);
  const bool camera_holds = out.status.camera != hrp::approach_status_t::CAMERA_STREAMING &&
                            flies_on_sightings(arm_state);
  if (!out.status.pose_usable || !have_target_ || camera_holds) {
    settled_ = 0;
    integral_.setZero();
    return out;
  }
  const Eigen::Isometry3d T_world_body = from_msg(pose->T_world_body);
  const Eigen::Vector3d normal = T_world_handrail_.linear().col(0);
  const double angle =
      Eigen::AngleAxisd(T_world_target_.linear() * T_world_body.linear().transpose()).angle();
  out.status.position_error_m =
      (T_world_target_ * p_body_grasp_ - T_world_body * p_body_grasp_).norm();
  out.status.angle_error_rad = angle;
  // How far out from the bar the body is, along the wall normal.
  const double out_m = normal.dot(T_world_body.translation() - T_world_handrail_.translation());

  if (arm_state == A::DEPLOYING || arm_state == A::CALIBRATING || arm_state == A::OPENING) {
    Eigen::Isometry3d goal = T_world_target_;
    goal.translation() += cfg_.standoff_m * normal;
    servo_to(T_world_body, goal, &out, dt_s, nullptr);
  } else if (arm_state == A::GRIPPER_OPEN) {
    const Eigen::Vector3d into_wall = -normal;
    servo_to(T_world_body, T_world_target_, &out, dt_s, &into_wall);
    const Eigen::Vector3d speed(pose->velocity_mps[0], pose->velocity_mps[1],
                                pose->velocity_mps[2]);
    const bool within = out.status.position_error_m <= cfg_.position_tolerance_m &&
                        angle <= cfg_.angle_tolerance_rad && speed.norm() <= cfg_.settle_speed_mps;
    settled_ = within ? settled_ + 1 : 0;
    out.status.at_target = settled_ >= cfg_.settle_cycles;
  } else if (arm_state == A::CLOSING || arm_state == A::GRASP_CHECK) {
    // Keep station on the grasp pose while the fingers close.
    servo_to(T_world_body, T_world_target_, &out, dt_s, nullptr);
    settled_ = 0;
  } else {
    settled_ = 0;
    integral_.setZero();
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
    servo_to(T_world_body, goal, &out, dt_s, nullptr);
    out.status.backed_off = out_m >= back_off_start_m_ + 0.9 * cfg_.back_off_m;
  } else {
    backing_off_ = false;
  }
  return out;
}

PerchManager::PerchManager(LcmHub& hub, const ApproachConfig& cfg,
                           const Eigen::Vector3d& p_body_grasp, const hal::Clock& clock,
                           double rate_hz)
    : hub_(hub),
      clock_(clock),
      controller_(cfg, p_body_grasp),
      period_us_(static_cast<std::int64_t>(1e6 / rate_hz)),
      velocity_pub_(hub, channel::kBodyVelocityCommand),
      status_pub_(hub, channel::kApproachStatus) {
  hub_.subscribe(channel::kHandrailEstimate, &estimate_box_);
  hub_.subscribe(channel::kRobotPose, &pose_box_);
  hub_.subscribe(channel::kArmState, &arm_box_);
  reserve_text(&arm_);
}

PerchManager::~PerchManager() {
  stop();
}

void PerchManager::start() {
  thread_.start(period_us_, [this] { cycle(); });
}

void PerchManager::stop() {
  thread_.stop();
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
