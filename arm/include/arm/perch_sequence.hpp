#pragma once
// The perch sequence as an explicit state machine:
//
//   INIT -> STOWED -PERCH-> DEPLOYING -> [CALIBRATING] -> OPENING -> GRIPPER_OPEN
//   -at target-> CLOSING -> GRASP_CHECK -> PERCHED <-> PAN_TILT
//   PERCHED -UNPERCH-> UNPERCHING -> BACKING_OFF -backed off-> STOWING -> STOWED
//
// A failed grasp reopens and waits for the approach again, a bounded number
// of times. Any fault (device silent or in error, grasp failed, handrail
// lost, a state past its timeout) goes to FAULT through one safe action:
// joints held where they are (torque off if a servo is in alarm), the
// gripper stopped unless it holds a handrail, in which case it keeps
// holding. A robot pose lost during the approach (POSE_LOST) folds the arm
// instead: the robot cannot tell where the wall is; so does a camera that
// delivers no frame (CAMERA_LOST): it cannot see the bar. Only STOWED, PERCHED
// and FAULT wait without a timeout.
//
// step() does all the I/O and is called at a fixed rate by the arm task,
// with the time injected. Nothing allocates; every loop is bounded.
#include <cstdint>

#include "arm/actuators.hpp"
#include "arm/perch_config.hpp"
#include "arm/perch_types.hpp"

namespace arm {

class PerchSequence {
 public:
  PerchSequence(JointActuators& joints, GripperActuator& gripper, const PerchConfig& config);

  // Validates a command on receipt. An accepted command is carried out by
  // the next step(); a rejected one is never acted on, and the reason shows
  // in status().last_reject.
  RejectCode submit(const PerchCommand& command);
  void set_approach(const ApproachInput& approach) { approach_ = approach; }

  // One control cycle: read the devices, check for faults, act on a
  // pending command, advance the state.
  void step(std::int64_t now_us);

  const ArmStatus& status() const { return status_; }
  PerchState state() const { return status_.state; }
  const PerchConfig& config() const { return config_; }
  // The state's timeout in ms, or 0 for the rest states.
  int timeout_ms(PerchState state) const;

 private:
  bool read_devices();
  bool check_device_faults();
  void run_command(const PerchCommand& command);
  void run_state();
  void advance_state();
  void enter(PerchState state);
  IoResult entry_action(PerchState state, const char** what);
  void run_entry_action();
  void fault(FaultCode code, const IoResult& io, const char* detail);
  void enter_safe_state(bool servo_alarm, bool fold);
  // Faults the approach when the perch manager has had no usable robot
  // pose for pose_lost_ms; true when it did.
  bool pose_lost();
  // The same for the camera: no frame for camera_lost_ms.
  bool camera_lost();
  // Shared by both: faults with `code` when `since_us` (>= 0) is older than
  // limit_ms, counted from the perch's start at the earliest.
  bool approach_input_lost(std::int64_t since_us, int limit_ms, FaultCode code, const char* detail);
  // Notes when frames come back after a gap (the handrail's allowance
  // restarts there).
  void note_camera_return();
  bool holding_handrail() const;
  bool joints_at(const JointAngles& goal) const;
  void judge_grasp();
  void start_stowing();

  JointActuators& joints_;
  GripperActuator& gripper_;
  PerchConfig config_;
  ArmStatus status_;
  ApproachInput approach_;
  std::int64_t now_us_ = 0;
  bool have_time_ = false;
  bool pending_ = false;
  PerchCommand pending_command_;
  std::uint8_t joint_failures_ = 0, gripper_failures_ = 0;
  // The state's entry commands were lost on the line (no reply, corrupt):
  // they are sent again each cycle, up to io_failures_to_fault cycles.
  bool entry_owed_ = false;
  std::uint8_t entry_failures_ = 0;
  // Where CALIBRATING goes when it finishes.
  PerchState after_calibration_ = PerchState::kStowed;
  std::int64_t hold_since_us_ = -1;       // grasp check: when the hold was first seen
  std::int64_t approach_started_us_ = 0;  // entry into DEPLOYING
  bool camera_was_late_ = false;
  std::int64_t camera_back_us_ = -1;  // when frames last came back after a gap
};

}  // namespace arm
