// The perch sequence's logic, fast and exhaustive, on in-memory devices
// and a manual clock: the whole happy path, command validation, each fault
// to its safe state with its reason, grasp retries, a restart while
// perched, and a randomised run proving no state outlives its timeout.
#include <cstdio>
#include <cstring>
#include <random>

#include "allocation_counter.hpp"
#include "arm/perch_sequence.hpp"
#include "cmocka_cpp.hpp"
#include "fake_arm_devices.hpp"

using arm::CommandKind;
using arm::FaultCode;
using arm::PerchState;
using arm::RejectCode;

namespace {

constexpr std::int64_t kStepUs = 50000;  // the arm task's 20 Hz

struct Rig {
  hal::ManualClock clock{1000000};
  FakeJoints joints{clock};
  FakeGripper gripper{clock};
  arm::PerchSequence seq{joints, gripper, arm::PerchConfig{}};
  arm::ApproachInput approach;

  void step() {
    clock.advance_us(kStepUs);
    approach.handrail_seen_us = seeing ? clock.now_us() : approach.handrail_seen_us;
    seq.set_approach(approach);
    seq.step(clock.now_us());
  }
  // Steps until the state is `want` or `seconds` pass.
  bool run_until(PerchState want, double seconds) {
    for (int k = 0; k < seconds * 1e6 / kStepUs; ++k) {
      step();
      if (seq.state() == want) return true;
    }
    print_error("wanted %s, in %s (fault %s)\n", arm::to_string(want), arm::to_string(seq.state()),
                seq.status().fault_text);
    return false;
  }
  RejectCode command(CommandKind kind, double tilt = 0.0, double pan = 0.0) {
    return seq.submit({static_cast<std::uint8_t>(kind), tilt, pan});
  }
  bool seeing = true;
};

void perch(Rig& rig) {
  rig.gripper.handrail_counts = 1800;
  assert_true(rig.run_until(PerchState::kStowed, 1.0));
  assert_int_equal(static_cast<int>(rig.command(CommandKind::kPerch)),
                   static_cast<int>(RejectCode::kAccepted));
  assert_true(rig.run_until(PerchState::kGripperOpen, 20.0));
  rig.approach.at_target = true;
  assert_true(rig.run_until(PerchState::kPerched, 10.0));
}

void test_happy_path_visits_every_state_in_order(void**) {
  Rig rig;
  PerchState seen[64];
  int n = 0;
  auto track = [&] {
    if (n == 0 || seen[n - 1] != rig.seq.state()) seen[n++] = rig.seq.state();
  };
  rig.gripper.handrail_counts = 1800;
  track();
  for (int k = 0; k < 10; ++k, track()) rig.step();
  rig.command(CommandKind::kPerch);
  for (int k = 0; k < 400 && rig.seq.state() != PerchState::kGripperOpen; ++k, track()) rig.step();
  for (int k = 0; k < 20; ++k, track()) rig.step();  // waiting for the approach
  rig.approach.at_target = true;
  for (int k = 0; k < 200 && rig.seq.state() != PerchState::kPerched; ++k, track()) rig.step();
  assert_int_equal(static_cast<int>(rig.command(CommandKind::kPanTilt, 0.5, -0.3)),
                   static_cast<int>(RejectCode::kAccepted));
  for (int k = 0; k < 100; ++k, track()) rig.step();
  assert_near(rig.joints.q.tilt_rad, 0.5, 0.035);
  assert_near(rig.joints.q.pan_rad, -0.3, 0.035);
  rig.approach.at_target = false;
  rig.command(CommandKind::kUnperch);
  for (int k = 0; k < 200 && rig.seq.state() != PerchState::kBackingOff; ++k, track()) rig.step();
  for (int k = 0; k < 5; ++k, track()) rig.step();
  rig.approach.backed_off = true;
  for (int k = 0; k < 400 && rig.seq.state() != PerchState::kStowed; ++k, track()) rig.step();
  const PerchState want[] = {
      PerchState::kInit,        PerchState::kStowed,     PerchState::kDeploying,
      PerchState::kCalibrating, PerchState::kOpening,    PerchState::kGripperOpen,
      PerchState::kClosing,     PerchState::kGraspCheck, PerchState::kPerched,
      PerchState::kPanTilt,     PerchState::kPerched,    PerchState::kUnperching,
      PerchState::kBackingOff,  PerchState::kStowing,    PerchState::kStowed};
  for (int k = 0; k < n; ++k) std::printf("%s ", arm::to_string(seen[k]));
  std::printf("\n");
  assert_int_equal(n, static_cast<int>(sizeof(want) / sizeof(want[0])));
  for (int k = 0; k < n; ++k)
    assert_int_equal(static_cast<int>(seen[k]), static_cast<int>(want[k]));
  assert_int_equal(static_cast<int>(rig.seq.status().last_grasp),
                   static_cast<int>(arm::GraspResult::kInHand));
  assert_int_equal(rig.gripper.calibrations, 1);     // calibrated once, on the way out
  assert_near(rig.gripper.position, 2000.0, 120.0);  // stowed with the fingers in
  assert_near(rig.joints.q.tilt_rad, M_PI / 2, 0.035);
}

void test_commands_are_validated_on_receipt(void**) {
  Rig rig;
  perch(rig);
  const std::uint32_t before = rig.seq.status().commands_rejected;
  // Out of range, not finite, unknown, wrong state, holding a handrail.
  assert_int_equal(static_cast<int>(rig.command(CommandKind::kPanTilt, 2.0, 0.0)),
                   static_cast<int>(RejectCode::kOutOfRange));
  assert_int_equal(static_cast<int>(rig.command(CommandKind::kPanTilt, NAN, 0.0)),
                   static_cast<int>(RejectCode::kOutOfRange));
  assert_int_equal(static_cast<int>(rig.seq.submit({99, 0.0, 0.0})),
                   static_cast<int>(RejectCode::kUnknownCommand));
  assert_int_equal(static_cast<int>(rig.seq.submit({0, 0.0, 0.0})),
                   static_cast<int>(RejectCode::kUnknownCommand));
  assert_int_equal(static_cast<int>(rig.command(CommandKind::kPerch)),
                   static_cast<int>(RejectCode::kNotAllowedInState));
  assert_int_equal(static_cast<int>(rig.command(CommandKind::kReconnect)),
                   static_cast<int>(RejectCode::kNotAllowedInState));
  assert_int_equal(rig.seq.status().commands_rejected, before + 6);
  assert_int_equal(static_cast<int>(rig.seq.status().last_reject),
                   static_cast<int>(RejectCode::kNotAllowedInState));
  // None of them was acted on.
  const int moves = rig.joints.moves;
  for (int k = 0; k < 20; ++k) rig.step();
  assert_int_equal(static_cast<int>(rig.seq.state()), static_cast<int>(PerchState::kPerched));
  assert_int_equal(rig.joints.moves, moves);
  // A fault while holding: STOW is refused, the grip is kept.
  rig.joints.silent = true;
  assert_true(rig.run_until(PerchState::kFault, 1.0));
  rig.joints.silent = false;
  for (int k = 0; k < 3; ++k) rig.step();
  assert_int_equal(static_cast<int>(rig.command(CommandKind::kStow)),
                   static_cast<int>(RejectCode::kHoldingHandrail));
  assert_int_equal(rig.gripper.stops, 0);
  assert_true(rig.gripper.holding);
}

void test_abort_during_the_approach_lets_go_and_stows(void**) {
  Rig rig;
  rig.gripper.handrail_counts = 1800;
  assert_true(rig.run_until(PerchState::kStowed, 1.0));
  rig.command(CommandKind::kPerch);
  assert_true(rig.run_until(PerchState::kGripperOpen, 20.0));
  rig.command(CommandKind::kAbort);
  assert_true(rig.run_until(PerchState::kBackingOff, 5.0));
  rig.approach.backed_off = true;
  assert_true(rig.run_until(PerchState::kStowed, 15.0));
}

void test_empty_close_is_retried_then_fails(void**) {
  Rig rig;
  rig.gripper.handrail_counts = -1;  // nothing between the fingers
  assert_true(rig.run_until(PerchState::kStowed, 1.0));
  rig.command(CommandKind::kPerch);
  assert_true(rig.run_until(PerchState::kGripperOpen, 20.0));
  rig.approach.at_target = true;
  assert_true(rig.run_until(PerchState::kFault, 30.0));
  const arm::ArmStatus& s = rig.seq.status();
  assert_int_equal(static_cast<int>(s.fault), static_cast<int>(FaultCode::kGraspFailed));
  assert_int_equal(s.grasp_attempts, 3);
  assert_int_equal(rig.gripper.closes, 3);
  assert_int_equal(static_cast<int>(s.last_grasp), static_cast<int>(arm::GraspResult::kEmpty));
  assert_non_null(std::strstr(s.fault_text, "GRASP_FAILED"));
  // A second attempt that finds the handrail succeeds.
  Rig again;
  again.gripper.handrail_counts = -1;
  assert_true(again.run_until(PerchState::kStowed, 1.0));
  again.command(CommandKind::kPerch);
  assert_true(again.run_until(PerchState::kGripperOpen, 20.0));
  again.approach.at_target = true;
  assert_true(again.run_until(PerchState::kOpening, 5.0));  // the first close was empty
  again.gripper.handrail_counts = 1800;                     // the robot settled onto the bar
  assert_true(again.run_until(PerchState::kPerched, 10.0));
  assert_int_equal(again.seq.status().grasp_attempts, 1);
}

void test_wrong_place_is_a_failed_grasp(void**) {
  Rig rig;
  rig.gripper.handrail_counts = 400;  // something much wider than a handrail
  assert_true(rig.run_until(PerchState::kStowed, 1.0));
  rig.command(CommandKind::kPerch);
  assert_true(rig.run_until(PerchState::kGripperOpen, 20.0));
  rig.approach.at_target = true;
  assert_true(rig.run_until(PerchState::kOpening, 5.0));  // first retry
  assert_int_equal(static_cast<int>(rig.seq.status().last_grasp),
                   static_cast<int>(arm::GraspResult::kWrongPlace));
}

void test_handrail_lost_for_a_second_is_survived_longer_is_a_fault(void**) {
  Rig rig;
  rig.gripper.handrail_counts = 1800;
  assert_true(rig.run_until(PerchState::kStowed, 1.0));
  rig.command(CommandKind::kPerch);
  assert_true(rig.run_until(PerchState::kGripperOpen, 20.0));
  rig.seeing = false;
  for (int k = 0; k < 20; ++k) rig.step();  // one second occluded
  assert_int_equal(static_cast<int>(rig.seq.state()), static_cast<int>(PerchState::kGripperOpen));
  rig.seeing = true;
  rig.step();
  rig.seeing = false;
  assert_true(rig.run_until(PerchState::kFault, 2.0));
  assert_int_equal(static_cast<int>(rig.seq.status().fault),
                   static_cast<int>(FaultCode::kHandrailLost));
  assert_int_equal(rig.gripper.stops, 1);  // not holding anything: motor stopped
}

// The perch manager has had no usable robot pose (stale, lost, not the
// filter's) for pose_lost_ms: the approach ends POSE_LOST with the arm
// folded to its stow posture and the gripper to its stow position (the
// robot cannot tell where the wall is). A shorter outage is ridden out.
void test_pose_lost_during_the_approach_folds_the_arm(void**) {
  Rig rig;
  rig.gripper.handrail_counts = 1800;
  assert_true(rig.run_until(PerchState::kStowed, 1.0));
  rig.command(CommandKind::kPerch);
  assert_true(rig.run_until(PerchState::kGripperOpen, 20.0));
  const arm::PerchConfig& cfg = rig.seq.config();
  rig.approach.pose_usable = false;
  rig.approach.pose_unusable_since_us = rig.clock.now_us();
  for (int k = 0; k < 30; ++k) rig.step();  // 1.5 s
  assert_int_equal(static_cast<int>(rig.seq.state()), static_cast<int>(PerchState::kGripperOpen));
  rig.approach.pose_usable = true;
  rig.approach.pose_unusable_since_us = -1;
  rig.step();
  rig.approach.pose_usable = false;
  rig.approach.pose_unusable_since_us = rig.clock.now_us();
  assert_true(rig.run_until(PerchState::kFault, 0.001 * cfg.pose_lost_ms + 0.2));
  assert_int_equal(static_cast<int>(rig.seq.status().fault),
                   static_cast<int>(FaultCode::kPoseLost));
  assert_string_equal(arm::to_string(rig.seq.status().fault), "POSE_LOST");
  for (int k = 0; k < 100; ++k) rig.step();  // 5 s to fold
  assert_near(rig.joints.q.tilt_rad, cfg.geometry.stow.tilt_rad, 0.02);
  assert_near(rig.joints.q.pan_rad, cfg.geometry.stow.pan_rad, 0.02);
  assert_near(rig.gripper.position, cfg.stow_gripper_counts, 2.0);
  assert_int_equal(static_cast<int>(rig.seq.state()), static_cast<int>(PerchState::kFault));
}

// A pose missing since before PERCH (the filter still starting) gets the
// whole allowance from the perch's start, then the same fault.
void test_pose_missing_before_the_perch_gets_the_allowance(void**) {
  Rig rig;
  rig.approach.pose_usable = false;
  rig.approach.pose_unusable_since_us = rig.clock.now_us();
  assert_true(rig.run_until(PerchState::kStowed, 1.0));
  for (int k = 0; k < 60; ++k) rig.step();  // 3 s without a pose, stowed: nothing to abort
  assert_int_equal(static_cast<int>(rig.seq.state()), static_cast<int>(PerchState::kStowed));
  rig.command(CommandKind::kPerch);
  for (int k = 0; k < 30; ++k) rig.step();  // 1.5 s into the perch
  assert_true(rig.seq.state() != PerchState::kFault);
  assert_true(rig.run_until(PerchState::kFault, 1.0));
  assert_int_equal(static_cast<int>(rig.seq.status().fault),
                   static_cast<int>(FaultCode::kPoseLost));
}

// Frames late (the perch manager holds the robot meanwhile): the approach
// waits through a gap shorter than camera_lost_ms, even one longer than
// handrail_lost_ms (no frame is not "no handrail"), and the handrail's
// allowance restarts when frames return; a longer gap ends the perch
// CAMERA_LOST with the arm folded, as POSE_LOST does.
void test_camera_lost_during_the_approach_holds_then_folds(void**) {
  Rig rig;
  rig.gripper.handrail_counts = 1800;
  assert_true(rig.run_until(PerchState::kStowed, 1.0));
  rig.command(CommandKind::kPerch);
  assert_true(rig.run_until(PerchState::kGripperOpen, 20.0));
  const arm::PerchConfig& cfg = rig.seq.config();
  const auto camera_late = [&rig](bool late) {
    rig.seeing = !late;
    rig.approach.camera_usable = !late;
    rig.approach.camera_late_since_us = late ? rig.clock.now_us() : -1;
  };
  // A gap of 2.5 s: past handrail_lost_ms, within camera_lost_ms.
  camera_late(true);
  const int gap_steps = static_cast<int>(2500000 / kStepUs);
  assert_true(2500 > cfg.handrail_lost_ms && 2500 < cfg.camera_lost_ms);
  for (int k = 0; k < gap_steps; ++k) rig.step();
  assert_int_equal(static_cast<int>(rig.seq.state()), static_cast<int>(PerchState::kGripperOpen));
  // Frames back, the handrail not yet seen in them: its allowance counts
  // from the frames' return, then HANDRAIL_LOST as ever.
  camera_late(false);
  rig.seeing = false;
  for (int k = 0; k < static_cast<int>(1000LL * cfg.handrail_lost_ms / kStepUs) - 2; ++k) {
    rig.step();
  }
  assert_int_equal(static_cast<int>(rig.seq.state()), static_cast<int>(PerchState::kGripperOpen));
  rig.seeing = true;
  for (int k = 0; k < 10; ++k) rig.step();
  assert_int_equal(static_cast<int>(rig.seq.state()), static_cast<int>(PerchState::kGripperOpen));
  // A gap past camera_lost_ms.
  camera_late(true);
  for (int k = 0; k < static_cast<int>(1000LL * cfg.camera_lost_ms / kStepUs) - 1; ++k) {
    rig.step();
  }
  assert_int_equal(static_cast<int>(rig.seq.state()), static_cast<int>(PerchState::kGripperOpen));
  assert_true(rig.run_until(PerchState::kFault, 0.2));
  assert_int_equal(static_cast<int>(rig.seq.status().fault),
                   static_cast<int>(FaultCode::kCameraLost));
  assert_string_equal(arm::to_string(rig.seq.status().fault), "CAMERA_LOST");
  for (int k = 0; k < 100; ++k) rig.step();  // 5 s to fold
  assert_near(rig.joints.q.tilt_rad, cfg.geometry.stow.tilt_rad, 0.02);
  assert_near(rig.joints.q.pan_rad, cfg.geometry.stow.pan_rad, 0.02);
  assert_near(rig.gripper.position, cfg.stow_gripper_counts, 2.0);
  assert_int_equal(static_cast<int>(rig.seq.state()), static_cast<int>(PerchState::kFault));
}

// Frames late once the fingers close: holding the bar needs no camera.
void test_camera_late_while_closing_is_no_fault(void**) {
  Rig rig;
  rig.gripper.handrail_counts = 1800;
  assert_true(rig.run_until(PerchState::kStowed, 1.0));
  rig.command(CommandKind::kPerch);
  assert_true(rig.run_until(PerchState::kGripperOpen, 20.0));
  rig.approach.at_target = true;
  assert_true(rig.run_until(PerchState::kClosing, 1.0));
  rig.approach.camera_usable = false;
  rig.approach.camera_late_since_us = rig.clock.now_us() - 10000000;  // long late
  assert_true(rig.run_until(PerchState::kPerched, 10.0));
  for (int k = 0; k < 20; ++k) rig.step();
  assert_int_equal(static_cast<int>(rig.seq.state()), static_cast<int>(PerchState::kPerched));
}

void test_servo_silent_mid_approach_is_a_fault_naming_it(void**) {
  Rig rig;
  rig.gripper.handrail_counts = 1800;
  assert_true(rig.run_until(PerchState::kStowed, 1.0));
  rig.command(CommandKind::kPerch);
  assert_true(rig.run_until(PerchState::kGripperOpen, 20.0));
  rig.joints.silent = true;
  rig.step();  // one failed read is ridden out
  assert_int_equal(static_cast<int>(rig.seq.state()), static_cast<int>(PerchState::kGripperOpen));
  rig.step();
  const arm::ArmStatus& s = rig.seq.status();
  assert_int_equal(static_cast<int>(s.state), static_cast<int>(PerchState::kFault));
  assert_int_equal(static_cast<int>(s.fault), static_cast<int>(FaultCode::kServoNoReply));
  assert_int_equal(static_cast<int>(s.fault_state), static_cast<int>(PerchState::kGripperOpen));
  assert_non_null(std::strstr(s.fault_text, "tilt servo"));
  // Reconnect once it answers again: back through INIT to a stowed arm.
  rig.joints.silent = false;
  assert_int_equal(static_cast<int>(rig.command(CommandKind::kReconnect)),
                   static_cast<int>(RejectCode::kAccepted));
  rig.approach.backed_off = true;
  assert_true(rig.run_until(PerchState::kStowed, 15.0));
  assert_int_equal(static_cast<int>(rig.seq.status().fault), static_cast<int>(FaultCode::kNone));
}

void test_servo_overload_goes_limp_with_the_reason(void**) {
  Rig rig;
  perch(rig);
  rig.command(CommandKind::kPanTilt, 0.8, 0.0);
  rig.step();
  rig.joints.error_bits = 0x20;  // overload
  rig.step();
  const arm::ArmStatus& s = rig.seq.status();
  assert_int_equal(static_cast<int>(s.fault), static_cast<int>(FaultCode::kServoError));
  assert_int_equal(s.fault_io.error_bits, 0x20);
  assert_int_equal(rig.joints.torque_offs, 1);
  assert_true(rig.gripper.holding);  // still holding the handrail
  assert_int_equal(rig.gripper.stops, 0);
}

void test_gripper_faults(void**) {
  {
    Rig rig;  // over-current while closing
    rig.gripper.handrail_counts = 1800;
    assert_true(rig.run_until(PerchState::kStowed, 1.0));
    rig.command(CommandKind::kPerch);
    assert_true(rig.run_until(PerchState::kGripperOpen, 20.0));
    rig.approach.at_target = true;
    assert_true(rig.run_until(PerchState::kClosing, 1.0));
    rig.gripper.over_current = true;
    rig.gripper.latched = 1u << 5;
    assert_true(rig.run_until(PerchState::kFault, 1.0));
    assert_int_equal(static_cast<int>(rig.seq.status().fault),
                     static_cast<int>(FaultCode::kGripperOverCurrent));
  }
  {
    Rig rig;  // the board reset while perched: safe start, grip lost
    perch(rig);
    rig.gripper.safe_start = true;
    rig.step();
    assert_int_equal(static_cast<int>(rig.seq.status().fault),
                     static_cast<int>(FaultCode::kGripperError));
  }
  {
    Rig rig;  // the board goes silent
    perch(rig);
    rig.gripper.silent = true;
    assert_true(rig.run_until(PerchState::kFault, 1.0));
    assert_int_equal(static_cast<int>(rig.seq.status().fault),
                     static_cast<int>(FaultCode::kGripperNoReply));
    // Cannot see the gripper after perching: assume it holds, refuse STOW.
    assert_int_equal(static_cast<int>(rig.command(CommandKind::kStow)),
                     static_cast<int>(RejectCode::kHoldingHandrail));
  }
}

// A state's entry command lost on the line (a corrupt reply) is sent again
// on the next cycle; lost twice in a row, the arm faults naming it.
void test_lost_entry_command_is_resent_then_faults(void**) {
  {
    Rig rig;
    assert_true(rig.run_until(PerchState::kStowed, 1.0));
    rig.gripper.lost_commands = 1;  // the calibrate after deploying
    perch(rig);
    assert_int_equal(rig.gripper.calibrations, 2);
    assert_int_equal(static_cast<int>(rig.seq.status().fault), static_cast<int>(FaultCode::kNone));
    rig.approach.at_target = false;
    rig.gripper.lost_commands = 2;  // both tries of the unperch's open
    rig.command(CommandKind::kUnperch);
    assert_true(rig.run_until(PerchState::kFault, 1.0));
    const arm::ArmStatus& s = rig.seq.status();
    assert_int_equal(static_cast<int>(s.fault), static_cast<int>(FaultCode::kGripperNoReply));
    assert_int_equal(static_cast<int>(s.fault_state), static_cast<int>(PerchState::kUnperching));
    assert_int_equal(static_cast<int>(s.fault_io.status),
                     static_cast<int>(arm::IoStatus::kCorrupt));
    assert_non_null(std::strstr(s.fault_text, "open refused"));
  }
}

// The loop descheduled past a state's deadline (a stalled host) while the
// state in fact finished: the fresh reading decides, not the clock.
void test_a_stall_past_the_deadline_is_judged_on_a_fresh_reading(void**) {
  Rig rig;
  assert_true(rig.run_until(PerchState::kStowed, 1.0));
  rig.command(CommandKind::kPerch);
  rig.step();
  assert_int_equal(static_cast<int>(rig.seq.state()), static_cast<int>(PerchState::kDeploying));
  rig.clock.advance_us(1000LL * rig.seq.timeout_ms(PerchState::kDeploying) + 1000000);
  rig.step();  // the joints got there meanwhile
  assert_int_equal(static_cast<int>(rig.seq.state()), static_cast<int>(PerchState::kCalibrating));
  assert_int_equal(static_cast<int>(rig.seq.status().fault), static_cast<int>(FaultCode::kNone));
}

void test_stuck_joint_times_out(void**) {
  Rig rig;
  assert_true(rig.run_until(PerchState::kStowed, 1.0));
  rig.joints.stuck = true;  // the deploy that failed on orbit
  rig.command(CommandKind::kPerch);
  assert_true(rig.run_until(PerchState::kFault, 10.0));
  const arm::ArmStatus& s = rig.seq.status();
  assert_int_equal(static_cast<int>(s.fault), static_cast<int>(FaultCode::kStateTimeout));
  assert_int_equal(static_cast<int>(s.fault_state), static_cast<int>(PerchState::kDeploying));
  // Abort can then stow once the joint is free again.
  rig.joints.stuck = false;
  assert_int_equal(static_cast<int>(rig.command(CommandKind::kStow)),
                   static_cast<int>(RejectCode::kAccepted));
  assert_true(rig.run_until(PerchState::kStowed, 20.0));
}

void test_restart_while_perched_keeps_holding(void**) {
  Rig rig;
  perch(rig);
  // A new sequence (the process restarted) over the same devices.
  arm::PerchSequence fresh(rig.joints, rig.gripper, arm::PerchConfig{});
  const int opens = rig.gripper.opens;
  for (int k = 0; k < 5; ++k) {
    rig.clock.advance_us(kStepUs);
    fresh.step(rig.clock.now_us());
  }
  assert_int_equal(static_cast<int>(fresh.state()), static_cast<int>(PerchState::kPerched));
  assert_int_equal(rig.gripper.opens, opens);
  assert_true(rig.gripper.holding);
}

void test_uncalibrated_gripper_is_calibrated_before_stowing(void**) {
  Rig rig;
  // Powered up deployed, gripper never calibrated: INIT stows, and
  // calibrates first so that the fingers can reach their stow position.
  rig.joints.q = rig.joints.goal = {0.0, 0.0};
  assert_true(rig.run_until(PerchState::kCalibrating, 1.0));
  assert_true(rig.run_until(PerchState::kStowing, 10.0));
  assert_true(rig.run_until(PerchState::kStowed, 10.0));
  assert_true(rig.gripper.calibrated);
  assert_near(rig.gripper.position, 2000.0, 120.0);
}

// Every non-rest state has a positive timeout; rest states have none.
void test_timeouts_cover_every_transient_state(void**) {
  hal::ManualClock clock;
  FakeJoints j(clock);
  FakeGripper g(clock);
  arm::PerchSequence seq(j, g, arm::PerchConfig{});
  for (int s = 0; s < arm::kNumPerchStates; ++s) {
    const PerchState state = static_cast<PerchState>(s);
    assert_string_not_equal(arm::to_string(state), "UNKNOWN");
    if (arm::is_rest_state(state)) {
      assert_int_equal(seq.timeout_ms(state), 0);
    } else {
      assert_true(seq.timeout_ms(state) > 0);
    }
  }
}

// Random commands, approach inputs and device faults for a long time, from
// many seeds: no transient state lasts past its timeout plus one step, and
// nothing allocates.
void test_no_state_outlives_its_timeout(void**) {
  long transitions = 0;
  int states_seen = 0;
  bool seen[arm::kNumPerchStates] = {};
  for (unsigned seed = 1; seed <= 40; ++seed) {
    Rig rig;
    std::mt19937 rng(seed);
    std::uniform_int_distribution<int> pick(0, 99);
    PerchState last = rig.seq.state();
    std::int64_t since = rig.clock.now_us();
    alloc_counter::arm();
    for (int k = 0; k < 6000; ++k) {
      const int r = pick(rng);
      if (r < 4)
        rig.seq.submit({static_cast<std::uint8_t>(pick(rng) % 9), 0.01 * (pick(rng) - 50),
                        0.01 * (pick(rng) - 50)});
      if (r == 10) rig.approach.at_target = !rig.approach.at_target;
      if (r == 11) rig.approach.backed_off = !rig.approach.backed_off;
      if (r == 12) rig.seeing = !rig.seeing;
      if (r == 13 && pick(rng) < 20) rig.joints.silent = !rig.joints.silent;
      if (r == 14 && pick(rng) < 20) rig.joints.stuck = !rig.joints.stuck;
      if (r == 15 && pick(rng) < 20) rig.gripper.silent = !rig.gripper.silent;
      if (r == 16 && pick(rng) < 10) rig.gripper.handrail_counts = pick(rng) < 50 ? 1800 : -1;
      if (r == 18 && pick(rng) < 30) rig.gripper.lost_commands = 1 + pick(rng) % 2;
      if (r == 17 && pick(rng) < 5) rig.joints.error_bits = rig.joints.error_bits ? 0 : 0x20;
      rig.step();
      const PerchState s = rig.seq.state();
      assert_true(static_cast<int>(s) < arm::kNumPerchStates);
      if (s != last) {
        ++transitions;
        last = s;
        since = rig.clock.now_us();
        if (!seen[static_cast<int>(s)]) {
          seen[static_cast<int>(s)] = true;
          ++states_seen;
        }
      } else if (!arm::is_rest_state(s)) {
        const std::int64_t limit = rig.seq.timeout_ms(s) * 1000LL + 2 * kStepUs;
        if (rig.clock.now_us() - since > limit) {
          print_error("seed %u: stuck in %s\n", seed, arm::to_string(s));
          fail();
        }
      }
    }
    assert_int_equal(alloc_counter::disarm(), 0);
  }
  std::printf("%ld transitions, %d of %d states visited\n", transitions, states_seen,
              arm::kNumPerchStates);
  assert_true(transitions > 500);
  assert_true(states_seen >= 12);
}

}  // namespace

int main() {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_happy_path_visits_every_state_in_order),
      cmocka_unit_test(test_commands_are_validated_on_receipt),
      cmocka_unit_test(test_abort_during_the_approach_lets_go_and_stows),
      cmocka_unit_test(test_empty_close_is_retried_then_fails),
      cmocka_unit_test(test_wrong_place_is_a_failed_grasp),
      cmocka_unit_test(test_handrail_lost_for_a_second_is_survived_longer_is_a_fault),
      cmocka_unit_test(test_pose_lost_during_the_approach_folds_the_arm),
      cmocka_unit_test(test_pose_missing_before_the_perch_gets_the_allowance),
      cmocka_unit_test(test_camera_lost_during_the_approach_holds_then_folds),
      cmocka_unit_test(test_camera_late_while_closing_is_no_fault),
      cmocka_unit_test(test_servo_silent_mid_approach_is_a_fault_naming_it),
      cmocka_unit_test(test_servo_overload_goes_limp_with_the_reason),
      cmocka_unit_test(test_gripper_faults),
      cmocka_unit_test(test_lost_entry_command_is_resent_then_faults),
      cmocka_unit_test(test_a_stall_past_the_deadline_is_judged_on_a_fresh_reading),
      cmocka_unit_test(test_stuck_joint_times_out),
      cmocka_unit_test(test_restart_while_perched_keeps_holding),
      cmocka_unit_test(test_uncalibrated_gripper_is_calibrated_before_stowing),
      cmocka_unit_test(test_timeouts_cover_every_transient_state),
      cmocka_unit_test(test_no_state_outlives_its_timeout),
  };
  return cmocka_run_group_tests(tests, nullptr, nullptr);
}
