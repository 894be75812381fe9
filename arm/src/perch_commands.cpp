// The perch sequence's commands: validated on receipt (submit), carried
// out by the next step (run_command). Split from perch_sequence.cpp, which
// holds the cycle, the device reads and the states.
#include <cmath>

#include "arm/perch_sequence.hpp"

namespace arm {

RejectCode PerchSequence::submit(const PerchCommand& command) {
  RejectCode code = RejectCode::kAccepted;
  const PerchState s = status_.state;
  if (command.kind == 0 || command.kind > kMaxCommandKind) {
    code = RejectCode::kUnknownCommand;
  } else {
    switch (static_cast<CommandKind>(command.kind)) {
      case CommandKind::kNone:
        code = RejectCode::kUnknownCommand;
        break;
      case CommandKind::kPerch:
        if (s != PerchState::kStowed) code = RejectCode::kNotAllowedInState;
        break;
      case CommandKind::kUnperch:
        if (s != PerchState::kOpening && s != PerchState::kGripperOpen &&
            s != PerchState::kClosing && s != PerchState::kGraspCheck &&
            s != PerchState::kPerched && s != PerchState::kPanTilt && s != PerchState::kFault) {
          code = RejectCode::kNotAllowedInState;
        }
        break;
      case CommandKind::kPanTilt: {
        const JointAngles q{command.tilt_rad, command.pan_rad};
        if (!std::isfinite(q.tilt_rad) || !std::isfinite(q.pan_rad) ||
            !config_.perched_tilt.contains(q.tilt_rad) ||
            !config_.perched_pan.contains(q.pan_rad) || !within_limits(config_.geometry, q)) {
          code = RejectCode::kOutOfRange;
        } else if (s != PerchState::kPerched && s != PerchState::kPanTilt) {
          code = RejectCode::kNotAllowedInState;
        }
        break;
      }
      case CommandKind::kStow:
      case CommandKind::kCalibrate: {
        const bool stow = command.kind == static_cast<std::uint8_t>(CommandKind::kStow);
        const bool allowed = stow ? (s == PerchState::kDeploying || s == PerchState::kCalibrating ||
                                     s == PerchState::kFault)
                                  : (s == PerchState::kStowed || s == PerchState::kFault);
        if (!allowed) {
          code = RejectCode::kNotAllowedInState;
        } else if (holding_handrail()) {
          code = RejectCode::kHoldingHandrail;
        }
        break;
      }
      case CommandKind::kAbort:
        break;
      case CommandKind::kReconnect:
        if (s != PerchState::kFault) code = RejectCode::kNotAllowedInState;
        break;
    }
  }
  status_.last_command = code == RejectCode::kUnknownCommand
                             ? CommandKind::kNone
                             : static_cast<CommandKind>(command.kind);
  status_.last_reject = code;
  if (code != RejectCode::kAccepted) {
    ++status_.commands_rejected;
    return code;
  }
  // One slot: a newer command replaces one the sequence has not run yet,
  // except that an abort is never overwritten.
  if (!(pending_ && pending_command_.kind == static_cast<std::uint8_t>(CommandKind::kAbort))) {
    pending_command_ = command;
  }
  pending_ = true;
  return code;
}

void PerchSequence::run_command(const PerchCommand& command) {
  const PerchState s = status_.state;
  switch (static_cast<CommandKind>(command.kind)) {
    case CommandKind::kNone:
      break;
    case CommandKind::kPerch:
      status_.grasp_attempts = 0;
      status_.last_grasp = GraspResult::kNone;
      enter(PerchState::kDeploying);
      break;
    case CommandKind::kUnperch:
      enter(PerchState::kUnperching);
      break;
    case CommandKind::kPanTilt:
      status_.joint_goal = {command.tilt_rad, command.pan_rad};
      enter(PerchState::kPanTilt);
      break;
    case CommandKind::kStow:
      start_stowing();
      break;
    case CommandKind::kCalibrate:
      after_calibration_ = s == PerchState::kStowed ? PerchState::kStowed : PerchState::kInit;
      enter(PerchState::kCalibrating);
      break;
    case CommandKind::kReconnect:
      enter(PerchState::kInit);
      break;
    case CommandKind::kAbort:
      switch (s) {
        case PerchState::kDeploying:
          start_stowing();
          break;
        case PerchState::kCalibrating:
          if (after_calibration_ == PerchState::kOpening) {
            start_stowing();
          } else {
            (void)gripper_.stop();
            fault(FaultCode::kAborted, {}, "calibration aborted");
          }
          break;
        case PerchState::kOpening:
        case PerchState::kGripperOpen:
        case PerchState::kClosing:
        case PerchState::kGraspCheck:
          enter(PerchState::kUnperching);
          break;
        case PerchState::kPanTilt:
          if (status_.joints_valid) {
            status_.joint_goal = status_.joints.q;  // stop where the joints are
            enter(PerchState::kPerched);
          }
          break;
        case PerchState::kUnperching:
        case PerchState::kBackingOff:
        case PerchState::kStowing:
          fault(FaultCode::kAborted, {}, "stopped by abort");
          break;
        case PerchState::kInit:
        case PerchState::kStowed:
        case PerchState::kPerched:
        case PerchState::kFault:
          break;  // nothing moving
      }
      break;
  }
}

}  // namespace arm
