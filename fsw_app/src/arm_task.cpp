#include "fsw_app/arm_task.hpp"

#include "fsw_app/msg_convert.hpp"

namespace fsw_app {

ArmTask::ArmTask(LcmHub& hub, arm::JointActuators& joints, arm::GripperActuator& gripper,
                 const arm::PerchConfig& config, const hal::Clock& clock, double rate_hz,
                 int rt_priority)
    : hub_(hub),
      clock_(clock),
      sequence_(joints, gripper, config),
      period_us_(static_cast<std::int64_t>(1e6 / rate_hz)),
      rt_priority_(rt_priority),
      state_pub_(hub, channel::kArmState) {
  hub_.subscribe(channel::kPerchCommand, &command_queue_);
  hub_.subscribe(channel::kApproachStatus, &approach_box_);
  reserve_text(&state_);
}

ArmTask::~ArmTask() {
  stop();
}

void ArmTask::start() {
  thread_.start(
      period_us_, [this] { cycle(); }, rt_priority_);
}

void ArmTask::stop() {
  thread_.stop();
}

void ArmTask::cycle() {
  // The sequence keeps one accepted command for its next step (an abort
  // is never replaced), but judges every one: each shows in ARM_STATE's
  // last command and rejection count. Bounded by the queue's capacity.
  for (std::size_t k = 0; k < kCommandQueue && command_queue_.pop(&command_); ++k) {
    last_sequence_ = command_.sequence;
    sequence_.submit(
        {static_cast<std::uint8_t>(command_.command), command_.tilt_rad, command_.pan_rad});
  }
  arm::ApproachInput in;
  if (approach_box_.read(&approach_) != 0) {
    in.handrail_seen_us = approach_.handrail_seen_utime;
    in.at_target = approach_.at_target;
    in.backed_off = approach_.backed_off;
    in.pose_usable = approach_.pose_usable;
    in.pose_unusable_since_us = approach_.pose_unusable_since_utime;
    in.camera_usable = approach_.camera == hrp::approach_status_t::CAMERA_STREAMING;
    in.camera_late_since_us = approach_.camera_late_since_utime;
  }
  sequence_.set_approach(in);
  sequence_.step(clock_.now_us());
  fill_state();
  state_pub_.publish(state_);
}

void ArmTask::fill_state() {
  const arm::ArmStatus& s = sequence_.status();
  hrp::arm_state_t& m = state_;
  m.utime = clock_.now_us();
  m.state = static_cast<std::int8_t>(s.state);
  m.state_name = arm::to_string(s.state);
  m.state_entered_utime = s.state_entered_us;
  m.fault_code = static_cast<std::int8_t>(s.fault);
  m.fault_name = arm::to_string(s.fault);
  m.fault_state = static_cast<std::int8_t>(s.fault_state);
  m.fault_text = s.fault_text;
  m.last_command_sequence = last_sequence_;
  m.last_command = static_cast<std::int8_t>(s.last_command);
  m.last_reject = static_cast<std::int8_t>(s.last_reject);
  m.last_reject_name = arm::to_string(s.last_reject);
  m.commands_rejected = static_cast<std::int32_t>(s.commands_rejected);
  m.commands_dropped = static_cast<std::int32_t>(command_queue_.overflows());
  m.tilt_rad = s.joints.q.tilt_rad;
  m.pan_rad = s.joints.q.pan_rad;
  m.tilt_goal_rad = s.joint_goal.tilt_rad;
  m.pan_goal_rad = s.joint_goal.pan_rad;
  m.joints_moving = s.joints.moving;
  m.joints_valid = s.joints_valid;
  m.tilt_error_bits = static_cast<std::int8_t>(s.joints.tilt_error_bits);
  m.pan_error_bits = static_cast<std::int8_t>(s.joints.pan_error_bits);
  m.gripper_position_counts = s.gripper.position_counts;
  m.gripper_current_ma = s.gripper.current_ma;
  m.gripper_calibrated = s.gripper.calibrated;
  m.gripper_holding = s.gripper.holding;
  m.gripper_valid = s.gripper_valid;
  m.gripper_error_bits = static_cast<std::int8_t>(s.gripper.latched_error);
  m.grasp_attempts = static_cast<std::int8_t>(s.grasp_attempts);
  m.last_grasp = static_cast<std::int8_t>(s.last_grasp);
}

}  // namespace fsw_app
