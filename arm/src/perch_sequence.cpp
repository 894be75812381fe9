#include "arm/perch_sequence.hpp"

#include <cmath>
#include <cstdio>

namespace arm {
namespace {

// Servo error bits that mean the servo cannot be trusted to hold or move:
// input voltage, angle limit, overheating, overload (Dynamixel 1.0 bits 0,
// 1, 2, 5). Range, checksum and instruction errors belong to single
// packets and come back as command failures instead.
constexpr std::uint8_t kServoFaultBits = 0x01 | 0x02 | 0x04 | 0x20;
constexpr std::uint8_t kServoAlarmBits = 0x04 | 0x20;  // the servo shut its torque off
// Gripper board latched errors that end a sequence: serial timeout and
// over-current (both leave the board in safe start). Line errors (framing,
// CRC) only cost a retried packet.
constexpr std::uint8_t kGripperTimeoutBit = 1u << 4;
constexpr std::uint8_t kGripperOverCurrentBit = 1u << 5;

bool is_servo(Device d) {
  return d == Device::kTiltServo || d == Device::kPanServo;
}

FaultCode fault_for_io(const IoResult& io) {
  if (io.status == IoStatus::kInvalid) return FaultCode::kCommandFailed;
  if (is_servo(io.device)) {
    return io.status == IoStatus::kDeviceError ? FaultCode::kServoError : FaultCode::kServoNoReply;
  }
  return io.status == IoStatus::kDeviceError ? FaultCode::kGripperError
                                             : FaultCode::kGripperNoReply;
}

// A packet lost or mangled on the line: worth sending again. A device
// error or a refused argument is not.
bool is_line_error(const IoResult& io) {
  return io.status == IoStatus::kNoReply || io.status == IoStatus::kCorrupt;
}

}  // namespace

PerchSequence::PerchSequence(JointActuators& joints, GripperActuator& gripper,
                             const PerchConfig& config)
    : joints_(joints), gripper_(gripper), config_(config) {}

int PerchSequence::timeout_ms(PerchState state) const {
  const StateTimeoutsMs& t = config_.timeouts;
  switch (state) {
    case PerchState::kInit:
      return t.init;
    case PerchState::kDeploying:
      return t.deploying;
    case PerchState::kCalibrating:
      return t.calibrating;
    case PerchState::kOpening:
      return t.opening;
    case PerchState::kGripperOpen:
      return t.gripper_open;
    case PerchState::kClosing:
      return t.closing;
    case PerchState::kGraspCheck:
      return t.grasp_check;
    case PerchState::kPanTilt:
      return t.pan_tilt;
    case PerchState::kUnperching:
      return t.unperching;
    case PerchState::kBackingOff:
      return t.backing_off;
    case PerchState::kStowing:
      return t.stowing;
    case PerchState::kStowed:
    case PerchState::kPerched:
    case PerchState::kFault:
      return 0;
  }
  return 1;  // an unnamed value still times out
}

void PerchSequence::step(std::int64_t now_us) {
  now_us_ = now_us;
  note_camera_return();
  if (!have_time_) {
    have_time_ = true;
    status_.state_entered_us = now_us;
    enter(PerchState::kInit);
  }
  const bool io_ok = read_devices();
  if (io_ok && status_.state != PerchState::kFault) check_device_faults();
  if (entry_owed_ && status_.state != PerchState::kFault) run_entry_action();
  if (pending_) {
    pending_ = false;
    const PerchCommand command = pending_command_;
    // The state may have moved since the command was accepted.
    if (submit(command) == RejectCode::kAccepted) {
      pending_ = false;
      run_command(command);
    }
  }
  run_state();
}

namespace {

// One device's read: the reading kept when it succeeded, the run of
// failures counted (saturating) when it did not.
template <typename Reading>
void note_read(const IoResult& r, const Reading& reading, Reading* kept, bool* valid,
               std::uint8_t* failures) {
  *valid = r.ok();
  if (r.ok()) {
    *kept = reading;
    *failures = 0;
  } else if (*failures < 255) {
    ++*failures;
  }
}

}  // namespace

bool PerchSequence::read_devices() {
  JointReading joints;
  const IoResult jr = joints_.read(&joints);
  note_read(jr, joints, &status_.joints, &status_.joints_valid, &joint_failures_);
  GripperReading gripper;
  const IoResult gr = gripper_.read(&gripper);
  note_read(gr, gripper, &status_.gripper, &status_.gripper_valid, &gripper_failures_);
  if (status_.state == PerchState::kFault) return jr.ok() && gr.ok();
  if (joint_failures_ >= config_.io_failures_to_fault) {
    fault(fault_for_io(jr), jr, "joint read failed");
    return false;
  }
  if (gripper_failures_ >= config_.io_failures_to_fault) {
    fault(fault_for_io(gr), gr, "gripper read failed");
    return false;
  }
  return jr.ok() && gr.ok();
}

bool PerchSequence::check_device_faults() {
  // INIT clears what a restart leaves behind (latched errors, safe start).
  if (status_.state == PerchState::kInit) return true;
  const JointReading& j = status_.joints;
  if (j.tilt_error_bits & kServoFaultBits) {
    fault(FaultCode::kServoError, {IoStatus::kDeviceError, Device::kTiltServo, j.tilt_error_bits},
          "servo reports an error");
    return false;
  }
  if (j.pan_error_bits & kServoFaultBits) {
    fault(FaultCode::kServoError, {IoStatus::kDeviceError, Device::kPanServo, j.pan_error_bits},
          "servo reports an error");
    return false;
  }
  const GripperReading& g = status_.gripper;
  const IoResult gio{IoStatus::kDeviceError, Device::kGripper, g.latched_error};
  if (g.over_current || (g.latched_error & kGripperOverCurrentBit)) {
    fault(FaultCode::kGripperOverCurrent, gio, "over the board's current limit");
    return false;
  }
  if (g.latched_error & kGripperTimeoutBit) {
    fault(FaultCode::kGripperError, gio, "the board's serial timeout expired");
    return false;
  }
  // Safe start outside INIT means the board reset or stopped itself.
  if (g.safe_start) {
    fault(FaultCode::kGripperError, gio, "the board is in safe start (reset?)");
    return false;
  }
  return true;
}

bool PerchSequence::holding_handrail() const {
  const PerchState s = status_.state;
  if (s == PerchState::kPerched || s == PerchState::kPanTilt) return true;
  if (s == PerchState::kFault &&
      (status_.fault_state == PerchState::kPerched ||
       status_.fault_state == PerchState::kPanTilt) &&
      !status_.gripper_valid) {
    return true;  // cannot see the gripper: assume it still holds
  }
  const GripperReading& g = status_.gripper;
  return status_.gripper_valid && g.calibrated && g.holding &&
         g.position_counts >= config_.grasp_min_counts &&
         g.position_counts <= config_.grasp_max_counts;
}

bool PerchSequence::joints_at(const JointAngles& goal) const {
  if (!status_.joints_valid) return false;
  const JointReading& j = status_.joints;
  return std::fabs(j.q.tilt_rad - goal.tilt_rad) <= config_.joint_tolerance_rad &&
         std::fabs(j.q.pan_rad - goal.pan_rad) <= config_.joint_tolerance_rad && !j.moving;
}

void PerchSequence::fault(FaultCode code, const IoResult& io, const char* detail) {
  if (status_.state == PerchState::kFault) return;  // keep the first cause
  status_.fault = code;
  status_.fault_state = status_.state;
  status_.fault_io = io;
  if (io.device != Device::kNone) {
    std::snprintf(status_.fault_text, sizeof(status_.fault_text), "%s in %s: %s (%s, %s, 0x%02x)",
                  to_string(code), to_string(status_.state), detail, to_string(io.device),
                  to_string(io.status), io.error_bits);
  } else {
    std::snprintf(status_.fault_text, sizeof(status_.fault_text), "%s in %s: %s", to_string(code),
                  to_string(status_.state), detail);
  }
  const bool servo_alarm = is_servo(io.device) && (io.error_bits & kServoAlarmBits) != 0;
  // A robot that no longer knows where it is, or no longer sees the bar,
  // must not keep an open gripper out toward a wall: the arm folds (the
  // devices are healthy).
  const bool fold =
      (code == FaultCode::kPoseLost || code == FaultCode::kCameraLost) && !holding_handrail();
  enter(PerchState::kFault);
  enter_safe_state(servo_alarm, fold);
}

void PerchSequence::enter_safe_state(bool servo_alarm, bool fold) {
  // Best effort: the devices may be the cause, so failures here are not
  // faults of their own.
  if (fold && status_.joints_valid) {
    if (status_.gripper_valid && status_.gripper.calibrated) {
      (void)gripper_.go_to(config_.stow_gripper_counts, config_.stow_speed);
    }
    status_.joint_goal = config_.geometry.stow;
    (void)joints_.move_to(status_.joint_goal, config_.joint_speed_rad_s);
    return;
  }
  if (servo_alarm) {
    (void)joints_.set_torque(false);  // limp rather than fight an overload
  } else if (status_.joints_valid) {
    status_.joint_goal = status_.joints.q;
    (void)joints_.move_to(status_.joints.q, config_.joint_speed_rad_s);
  }
  if (!holding_handrail() && status_.gripper_valid) (void)gripper_.stop();
}

void PerchSequence::enter(PerchState state) {
  if (state != PerchState::kFault && status_.state == PerchState::kFault) {
    status_.fault = FaultCode::kNone;
    status_.fault_io = IoResult{};
    status_.fault_text[0] = '\0';
  }
  status_.state = state;
  status_.state_entered_us = now_us_;
  entry_owed_ = false;
  entry_failures_ = 0;
  switch (state) {
    case PerchState::kDeploying:
      approach_started_us_ = now_us_;
      break;
    case PerchState::kInit:
      joint_failures_ = gripper_failures_ = 0;
      // A restart may find a servo in alarm or the board in safe start
      // with errors latched: clear both before judging the arm's pose
      // (best effort: run_state recovers again until they read clean).
      (void)joints_.recover();
      (void)gripper_.recover();
      break;
    case PerchState::kGraspCheck:
      hold_since_us_ = -1;
      break;
    default:
      break;
  }
  run_entry_action();
}

IoResult PerchSequence::entry_action(PerchState state, const char** what) {
  IoResult io;
  switch (state) {
    case PerchState::kDeploying:
      *what = "torque enable refused";
      io = joints_.set_torque(true);
      if (!io.ok()) return io;
      *what = "joint move refused";
      status_.joint_goal = config_.geometry.deploy;
      return joints_.move_to(status_.joint_goal, config_.joint_speed_rad_s);
    case PerchState::kCalibrating:
      *what = "calibrate refused";
      return gripper_.calibrate();
    case PerchState::kOpening:
    case PerchState::kUnperching:
      *what = "open refused";
      return gripper_.open(config_.open_speed);
    case PerchState::kClosing:
      *what = "close refused";
      return gripper_.close(config_.close_speed, config_.close_current_limit_ma);
    case PerchState::kStowing:
      *what = "gripper stow refused";
      io = gripper_.go_to(config_.stow_gripper_counts, config_.stow_speed);
      if (!io.ok()) return io;
      *what = "torque enable refused";
      io = joints_.set_torque(true);
      if (!io.ok()) return io;
      *what = "joint move refused";
      status_.joint_goal = config_.geometry.stow;
      return joints_.move_to(status_.joint_goal, config_.joint_speed_rad_s);
    case PerchState::kPanTilt:
    case PerchState::kPerched:
      // The goal was set before entry: a validated pan / tilt command, or
      // where the joints are when the grip closed (hold them there).
      *what = "joint move refused";
      return joints_.move_to(status_.joint_goal, config_.joint_speed_rad_s);
    case PerchState::kInit:
    case PerchState::kStowed:
    case PerchState::kGripperOpen:
    case PerchState::kGraspCheck:
    case PerchState::kBackingOff:
    case PerchState::kFault:
      break;
  }
  return io;
}

void PerchSequence::run_entry_action() {
  const char* what = "";
  const IoResult io = entry_action(status_.state, &what);
  if (io.ok()) {
    entry_owed_ = false;
    return;
  }
  // Every entry action is safe to repeat (the same goal, the same open or
  // close, a calibration restarted), so a packet lost on a noisy line costs
  // a cycle, not the perch.
  if (entry_failures_ < 255) ++entry_failures_;
  if (is_line_error(io) && entry_failures_ < config_.io_failures_to_fault) {
    entry_owed_ = true;
    return;
  }
  fault(fault_for_io(io), io, what);
}

bool PerchSequence::approach_input_lost(std::int64_t since_us, int limit_ms, FaultCode code,
                                        const char* detail) {
  // Only while flying toward a perch: CLOSING and GRASP_CHECK finish on
  // the bar (holding it needs neither pose nor frames), and a calibration
  // for a stow leads away from the wall anyway.
  if (status_.state == PerchState::kCalibrating && after_calibration_ != PerchState::kOpening) {
    return false;
  }
  if (since_us < 0) return false;
  // Counted from the perch's start at the earliest: an input missing
  // before PERCH (a filter or a camera still starting) gets the whole
  // allowance.
  const std::int64_t since = since_us > approach_started_us_ ? since_us : approach_started_us_;
  if (now_us_ - since <= limit_ms * 1000LL) return false;
  fault(code, {}, detail);
  return true;
}

bool PerchSequence::pose_lost() {
  if (approach_.pose_usable) return false;
  return approach_input_lost(approach_.pose_unusable_since_us, config_.pose_lost_ms,
                             FaultCode::kPoseLost, "no usable robot pose during the approach");
}

bool PerchSequence::camera_lost() {
  if (approach_.camera_usable) return false;
  return approach_input_lost(approach_.camera_late_since_us, config_.camera_lost_ms,
                             FaultCode::kCameraLost, "no camera frame during the approach");
}

void PerchSequence::note_camera_return() {
  const bool late = !approach_.camera_usable;
  if (camera_was_late_ && !late) camera_back_us_ = now_us_;
  camera_was_late_ = late;
}

void PerchSequence::start_stowing() {
  // An uncalibrated gripper cannot go to its stow position (in operations
  // this made stowing fail): calibrate first, then stow.
  if (status_.gripper_valid && !status_.gripper.calibrated) {
    after_calibration_ = PerchState::kStowing;
    enter(PerchState::kCalibrating);
    return;
  }
  enter(PerchState::kStowing);
}

void PerchSequence::judge_grasp() {
  const std::int64_t in_state_us = now_us_ - status_.state_entered_us;
  if (in_state_us < config_.grasp_settle_ms * 1000LL || !status_.gripper_valid) return;
  const GripperReading& g = status_.gripper;
  GraspResult result = GraspResult::kNone;
  if (g.position_counts > config_.grasp_max_counts) {
    result = GraspResult::kEmpty;
  } else if (g.position_counts < config_.grasp_min_counts || g.stalled) {
    result = GraspResult::kWrongPlace;
  } else if (g.holding && g.current_ma >= config_.grasp_min_current_ma) {
    result = GraspResult::kInHand;
  } else if (!g.moving) {
    result = GraspResult::kNotHolding;
  }
  if (result == GraspResult::kNone) return;  // still settling; the timeout bounds it
  status_.last_grasp = result;
  if (result == GraspResult::kInHand) {
    status_.joint_goal = status_.joints.q;
    enter(PerchState::kPerched);
    return;
  }
  if (status_.grasp_attempts < 255) ++status_.grasp_attempts;
  if (status_.grasp_attempts >= config_.max_grasp_attempts) {
    char detail[48];
    std::snprintf(detail, sizeof(detail), "%u attempts, last %s", status_.grasp_attempts,
                  to_string(result));
    fault(FaultCode::kGraspFailed, {}, detail);
    return;
  }
  enter(PerchState::kOpening);  // open and close again once at the target
}

void PerchSequence::run_state() {
  const PerchState s = status_.state;
  const std::int64_t entered_us = status_.state_entered_us;
  const int timeout = timeout_ms(s);
  const bool overdue = timeout > 0 && now_us_ - entered_us > timeout * 1000LL;
  // The state gets this cycle's fresh reading before its timeout is
  // judged: a loop descheduled past the deadline (a stalled host) must
  // not fault a state that has in fact finished.
  if (!entry_owed_) advance_state();
  if (overdue && status_.state == s && status_.state_entered_us == entered_us) {
    fault(FaultCode::kStateTimeout, {}, "state timed out");
  }
}

void PerchSequence::advance_state() {
  const PerchState s = status_.state;
  const GripperReading& g = status_.gripper;
  const bool g_ok = status_.gripper_valid;
  const std::int64_t in_state_us = now_us_ - status_.state_entered_us;
  switch (s) {
    case PerchState::kInit:
      if (!status_.joints_valid || !g_ok) return;  // retried until the timeout
      // The recovery at entry may itself have been lost on a noisy line:
      // until the devices read back clean, recover again (bounded by the
      // INIT timeout).
      if (g.safe_start || (g.latched_error & (kGripperTimeoutBit | kGripperOverCurrentBit))) {
        (void)gripper_.recover();
        return;
      }
      if ((status_.joints.tilt_error_bits | status_.joints.pan_error_bits) & kServoAlarmBits) {
        (void)joints_.recover();
        return;
      }
      if (holding_handrail()) {
        // Restarted while perched: keep holding, never let go on our own.
        status_.joint_goal = status_.joints.q;
        enter(PerchState::kPerched);
      } else if (joints_at(config_.geometry.stow)) {
        enter(PerchState::kStowed);
      } else {
        start_stowing();
      }
      return;
    case PerchState::kDeploying:
      if (pose_lost() || camera_lost()) return;
      if (!joints_at(config_.geometry.deploy)) return;
      if (g_ok && !g.calibrated) {
        after_calibration_ = PerchState::kOpening;
        enter(PerchState::kCalibrating);
      } else if (g_ok) {
        enter(PerchState::kOpening);
      }
      return;
    case PerchState::kCalibrating:
      if (pose_lost() || camera_lost()) return;
      if (g_ok && g.calibrated && !g.moving && in_state_us > 100000) enter(after_calibration_);
      return;
    case PerchState::kOpening:
      if (pose_lost() || camera_lost()) return;
      if (g_ok && g.position_counts <= config_.open_done_counts && !g.moving) {
        enter(PerchState::kGripperOpen);
      }
      return;
    case PerchState::kGripperOpen: {
      if (pose_lost() || camera_lost()) return;
      // No frame is not "no handrail": while frames are missing the camera
      // rule above decides, and the handrail's allowance restarts when
      // they come back.
      if (!approach_.camera_usable) return;
      std::int64_t seen = approach_.handrail_seen_us > status_.state_entered_us
                              ? approach_.handrail_seen_us
                              : status_.state_entered_us;
      if (camera_back_us_ > seen) seen = camera_back_us_;
      if (now_us_ - seen > config_.handrail_lost_ms * 1000LL) {
        fault(FaultCode::kHandrailLost, {}, "no handrail estimate during the approach");
      } else if (approach_.at_target) {
        enter(PerchState::kClosing);
      }
      return;
    }
    case PerchState::kClosing:
      if (!g_ok) return;
      if (g.holding || g.stalled || (!g.moving && in_state_us > 300000)) {
        enter(PerchState::kGraspCheck);
      }
      return;
    case PerchState::kGraspCheck:
      judge_grasp();
      return;
    case PerchState::kPerched:
    case PerchState::kPanTilt:
      if (g_ok && (!g.holding || g.position_counts < config_.grasp_min_counts ||
                   g.position_counts > config_.grasp_max_counts)) {
        fault(FaultCode::kGripLost, {}, "the gripper no longer holds the handrail");
        return;
      }
      if (s == PerchState::kPanTilt && joints_at(status_.joint_goal)) enter(PerchState::kPerched);
      return;
    case PerchState::kUnperching:
      if (g_ok && g.position_counts <= config_.open_done_counts && !g.moving) {
        enter(PerchState::kBackingOff);
      }
      return;
    case PerchState::kBackingOff:
      if (approach_.backed_off) start_stowing();
      return;
    case PerchState::kStowing: {
      const bool gripper_stowed = g_ok &&
                                  std::abs(g.position_counts - config_.stow_gripper_counts) <=
                                      config_.stow_gripper_tolerance &&
                                  !g.moving;
      if (gripper_stowed && joints_at(config_.geometry.stow)) enter(PerchState::kStowed);
      return;
    }
    case PerchState::kStowed:
    case PerchState::kFault:
      return;
  }
}

}  // namespace arm
