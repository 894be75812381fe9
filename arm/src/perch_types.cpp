#include "arm/perch_types.hpp"

namespace arm {

const char* to_string(IoStatus status) {
  switch (status) {
    case IoStatus::kOk:
      return "OK";
    case IoStatus::kNoReply:
      return "NO_REPLY";
    case IoStatus::kCorrupt:
      return "CORRUPT";
    case IoStatus::kPortError:
      return "PORT_ERROR";
    case IoStatus::kInvalid:
      return "INVALID";
    case IoStatus::kDeviceError:
      return "DEVICE_ERROR";
  }
  return "UNKNOWN";
}

const char* to_string(Device device) {
  switch (device) {
    case Device::kNone:
      return "none";
    case Device::kTiltServo:
      return "tilt servo";
    case Device::kPanServo:
      return "pan servo";
    case Device::kGripper:
      return "gripper board";
  }
  return "unknown device";
}

const char* to_string(PerchState state) {
  switch (state) {
    case PerchState::kInit:
      return "INIT";
    case PerchState::kStowed:
      return "STOWED";
    case PerchState::kDeploying:
      return "DEPLOYING";
    case PerchState::kCalibrating:
      return "CALIBRATING";
    case PerchState::kOpening:
      return "OPENING";
    case PerchState::kGripperOpen:
      return "GRIPPER_OPEN";
    case PerchState::kClosing:
      return "CLOSING";
    case PerchState::kGraspCheck:
      return "GRASP_CHECK";
    case PerchState::kPerched:
      return "PERCHED";
    case PerchState::kPanTilt:
      return "PAN_TILT";
    case PerchState::kUnperching:
      return "UNPERCHING";
    case PerchState::kBackingOff:
      return "BACKING_OFF";
    case PerchState::kStowing:
      return "STOWING";
    case PerchState::kFault:
      return "FAULT";
  }
  return "UNKNOWN";
}

bool is_rest_state(PerchState state) {
  return state == PerchState::kStowed || state == PerchState::kPerched ||
         state == PerchState::kFault;
}

const char* to_string(FaultCode code) {
  switch (code) {
    case FaultCode::kNone:
      return "NONE";
    case FaultCode::kServoNoReply:
      return "SERVO_NO_REPLY";
    case FaultCode::kServoError:
      return "SERVO_ERROR";
    case FaultCode::kGripperNoReply:
      return "GRIPPER_NO_REPLY";
    case FaultCode::kGripperOverCurrent:
      return "GRIPPER_OVER_CURRENT";
    case FaultCode::kGripperError:
      return "GRIPPER_ERROR";
    case FaultCode::kGripperNotCalibrated:
      return "GRIPPER_NOT_CALIBRATED";
    case FaultCode::kGraspFailed:
      return "GRASP_FAILED";
    case FaultCode::kHandrailLost:
      return "HANDRAIL_LOST";
    case FaultCode::kPoseLost:
      return "POSE_LOST";
    case FaultCode::kCameraLost:
      return "CAMERA_LOST";
    case FaultCode::kGripLost:
      return "GRIP_LOST";
    case FaultCode::kStateTimeout:
      return "STATE_TIMEOUT";
    case FaultCode::kCommandFailed:
      return "COMMAND_FAILED";
    case FaultCode::kAborted:
      return "ABORTED";
    case FaultCode::kStartupUnknown:
      return "STARTUP_UNKNOWN";
  }
  return "UNKNOWN";
}

const char* to_string(CommandKind kind) {
  switch (kind) {
    case CommandKind::kNone:
      return "NONE";
    case CommandKind::kPerch:
      return "PERCH";
    case CommandKind::kUnperch:
      return "UNPERCH";
    case CommandKind::kPanTilt:
      return "PAN_TILT";
    case CommandKind::kStow:
      return "STOW";
    case CommandKind::kCalibrate:
      return "CALIBRATE";
    case CommandKind::kAbort:
      return "ABORT";
    case CommandKind::kReconnect:
      return "RECONNECT";
  }
  return "UNKNOWN";
}

const char* to_string(RejectCode code) {
  switch (code) {
    case RejectCode::kAccepted:
      return "ACCEPTED";
    case RejectCode::kUnknownCommand:
      return "UNKNOWN_COMMAND";
    case RejectCode::kOutOfRange:
      return "OUT_OF_RANGE";
    case RejectCode::kNotAllowedInState:
      return "NOT_ALLOWED_IN_STATE";
    case RejectCode::kHoldingHandrail:
      return "HOLDING_HANDRAIL";
  }
  return "UNKNOWN";
}

const char* to_string(GraspResult result) {
  switch (result) {
    case GraspResult::kNone:
      return "NONE";
    case GraspResult::kInHand:
      return "IN_HAND";
    case GraspResult::kEmpty:
      return "EMPTY";
    case GraspResult::kWrongPlace:
      return "WRONG_PLACE";
    case GraspResult::kNotHolding:
      return "NOT_HOLDING";
  }
  return "UNKNOWN";
}

}  // namespace arm
