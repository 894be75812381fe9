#pragma once
// The perch sequence's vocabulary: states, commands, reasons, and what it
// reports. Every enum has a to_string for logs and the arm state message.
#include <cstdint>

#include "arm/actuators.hpp"

namespace arm {

enum class PerchState : std::uint8_t {
  kInit,         // reading the devices and working out where the arm is
  kStowed,       // rest: folded, waiting for PERCH
  kDeploying,    // joints to the deploy posture
  kCalibrating,  // gripper to its open stop to zero the encoder
  kOpening,      // gripper opening for a grasp
  kGripperOpen,  // open and waiting while the robot approaches the target
  kClosing,      // gripper closing on the handrail
  kGraspCheck,   // judging the close: handrail in hand, empty, or wrong place
  kPerched,      // rest: holding the handrail
  kPanTilt,      // perched, joints moving to a commanded pan / tilt
  kUnperching,   // gripper opening to let go
  kBackingOff,   // open, waiting while the robot moves away
  kStowing,      // gripper to its stow position and joints to stow
  kFault,        // rest: safe state, with a reason
};
constexpr int kNumPerchStates = 14;
const char* to_string(PerchState state);
// Rest states wait for a command by design; every other state has a timeout.
bool is_rest_state(PerchState state);

// Why the sequence is in kFault.
enum class FaultCode : std::uint8_t {
  kNone,
  kServoNoReply,          // a joint servo stopped answering (or answers garbage)
  kServoError,            // a servo reported error bits (overload, heat, voltage...)
  kGripperNoReply,        // the gripper board stopped answering
  kGripperOverCurrent,    // the board tripped its absolute current limit
  kGripperError,          // the board latched an error (serial timeout, ...)
  kGripperNotCalibrated,  // calibration did not finish at the open stop
  kGraspFailed,           // every grasp attempt was empty or in the wrong place
  kHandrailLost,          // no handrail estimate for too long during the approach
  kGripLost,              // perched, and the gripper no longer holds the handrail
  kStateTimeout,          // a state ran past its timeout (see fault_state)
  kCommandFailed,         // a device refused a command it should take
  kAborted,               // the operator aborted a stow or an unperch
  kStartupUnknown,        // at start the arm was neither stowed nor holding, and could not stow
  kPoseLost,              // no usable robot pose for too long during the approach (arm stowed)
  kCameraLost,            // no camera frame for too long during the approach (arm stowed)
};
const char* to_string(FaultCode code);

enum class CommandKind : std::uint8_t {
  kNone = 0,
  kPerch = 1,      // deploy, open, wait for the approach, close, check
  kUnperch = 2,    // open, back off, stow
  kPanTilt = 3,    // perched: point the body with the joints
  kStow = 4,       // fold the arm (not while holding a handrail)
  kCalibrate = 5,  // zero the gripper's encoder at its open stop
  kAbort = 6,      // stop what is under way, in the safest way for the state
  kReconnect = 7,  // from a fault: recover the devices and start over
};
constexpr std::uint8_t kMaxCommandKind = 7;
const char* to_string(CommandKind kind);

struct PerchCommand {
  std::uint8_t kind = 0;  // CommandKind as it came off the wire
  double tilt_rad = 0.0;  // for kPanTilt
  double pan_rad = 0.0;
};

enum class RejectCode : std::uint8_t {
  kAccepted,
  kUnknownCommand,     // a kind that is not a CommandKind
  kOutOfRange,         // angles outside the perched limits, or not finite
  kNotAllowedInState,  // e.g. PERCH while perched
  kHoldingHandrail,    // STOW or CALIBRATE while the gripper holds a handrail
};
const char* to_string(RejectCode code);

// What the grasp check concluded.
enum class GraspResult : std::uint8_t { kNone, kInHand, kEmpty, kWrongPlace, kNotHolding };
const char* to_string(GraspResult result);

// From the perch manager (or an operator): the approach's progress.
struct ApproachInput {
  std::int64_t handrail_seen_us = -1;  // capture time of the last estimate with a pose; -1 never
  bool at_target = false;              // the robot is at the grasp pose, within tolerance
  bool backed_off = false;             // after letting go, the robot is clear of the handrail
  bool pose_usable = true;             // the manager flies on a fresh, trusted robot pose
  std::int64_t pose_unusable_since_us = -1;  // since when it has none; -1 while it has one
  bool camera_usable = true;                 // frames arrive: the manager flies on fresh sightings
  std::int64_t camera_late_since_us = -1;    // since when they are late; -1 while they arrive
};

struct ArmStatus {
  PerchState state = PerchState::kInit;
  std::int64_t state_entered_us = 0;
  FaultCode fault = FaultCode::kNone;
  PerchState fault_state = PerchState::kInit;  // where the fault happened
  IoResult fault_io;                           // the device and its bits, for I/O faults
  char fault_text[128] = {};                   // one line for people
  CommandKind last_command = CommandKind::kNone;
  RejectCode last_reject = RejectCode::kAccepted;
  std::uint32_t commands_rejected = 0;
  GraspResult last_grasp = GraspResult::kNone;
  std::uint8_t grasp_attempts = 0;
  JointReading joints;
  GripperReading gripper;
  bool joints_valid = false, gripper_valid = false;  // the last reads succeeded
  JointAngles joint_goal;
};

}  // namespace arm
