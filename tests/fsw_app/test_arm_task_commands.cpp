// The arm task's command intake over real LCM (memq://): every command that
// arrives within one cycle is validated and answered in order (the old
// single-message mailbox kept only the newest, so an earlier bad command
// was never reported), a flood beyond the queue drops the oldest and counts
// them in ARM_STATE, and a malformed message changes nothing.
#include <lcm/lcm-cpp.hpp>

#include <cstdint>

#include "../arm/fake_arm_devices.hpp"
#include "cmocka_cpp.hpp"
#include "fsw_app/arm_task.hpp"

namespace {

struct Rig {
  hal::ManualClock clock{1000000};
  fsw_app::LcmHub hub{"memq://", clock};
  FakeJoints joints{clock};
  FakeGripper gripper{clock};
  fsw_app::ArmTask task{hub, joints, gripper, arm::PerchConfig{}, clock, 20.0};
  fsw_app::Publisher<hrp::perch_command_t> commands{hub, fsw_app::channel::kPerchCommand};

  // Cycles until the arm rests in STOWED (it starts in INIT).
  void settle() {
    for (int k = 0; k < 100 && task.sequence().state() != arm::PerchState::kStowed; ++k) cycle();
    assert_int_equal(static_cast<int>(task.sequence().state()),
                     static_cast<int>(arm::PerchState::kStowed));
  }
  void cycle() {
    clock.advance_us(50000);
    task.cycle();
  }
  void send(std::int32_t sequence, std::int8_t command, double tilt = 0.0, double pan = 0.0) {
    hrp::perch_command_t c{};
    c.utime = clock.now_us();
    c.sequence = sequence;
    c.command = command;
    c.tilt_rad = tilt;
    c.pan_rad = pan;
    assert_true(commands.publish(c));
  }
  // memq delivers on the dispatcher's call: one message per handle().
  void deliver_all() {
    while (hub.handle(0) > 0) {
    }
  }
};

void test_every_command_in_a_cycle_is_judged_in_order(void**) {
  Rig rig;
  rig.settle();
  rig.send(1, 42);                                   // unknown command
  rig.send(2, hrp::perch_command_t::PAN_TILT, 0.1);  // not while stowed
  rig.send(3, hrp::perch_command_t::PERCH);
  rig.deliver_all();
  rig.cycle();
  const hrp::arm_state_t& s = rig.task.last_state();
  assert_int_equal(s.commands_rejected, 2);
  assert_int_equal(s.commands_dropped, 0);
  assert_int_equal(s.last_command_sequence, 3);
  assert_int_equal(s.last_reject, 0);  // PERCH accepted
  assert_int_equal(s.state, hrp::arm_state_t::DEPLOYING);
}

void test_a_flood_drops_the_oldest_and_counts_them(void**) {
  Rig rig;
  rig.settle();
  // Eleven in one cycle: three more than the queue holds.
  for (std::int32_t k = 1; k <= 10; ++k) rig.send(k, 42);
  rig.send(11, hrp::perch_command_t::PERCH);
  rig.deliver_all();
  rig.cycle();
  const hrp::arm_state_t& s = rig.task.last_state();
  assert_int_equal(s.commands_dropped, 3);
  assert_int_equal(s.commands_rejected, 7);  // commands 4..10; the newest, PERCH, kept
  assert_int_equal(s.last_command_sequence, 11);
  assert_int_equal(s.state, hrp::arm_state_t::DEPLOYING);
  // The queue is empty again: nothing more is judged next cycle.
  rig.cycle();
  assert_int_equal(rig.task.last_state().commands_rejected, 7);
}

void test_a_malformed_command_changes_nothing(void**) {
  Rig rig;
  rig.settle();
  rig.send(1, 42);
  const std::uint8_t junk[5] = {1, 2, 3, 4, 5};
  assert_true(rig.hub.publish_raw(fsw_app::channel::kPerchCommand, junk, sizeof junk));
  rig.deliver_all();
  rig.cycle();
  const hrp::arm_state_t& s = rig.task.last_state();
  assert_int_equal(s.commands_rejected, 1);
  assert_int_equal(s.last_command_sequence, 1);
  assert_int_equal(s.state, hrp::arm_state_t::STOWED);
}

}  // namespace

int main() {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_every_command_in_a_cycle_is_judged_in_order),
      cmocka_unit_test(test_a_flood_drops_the_oldest_and_counts_them),
      cmocka_unit_test(test_a_malformed_command_changes_nothing),
  };
  return cmocka_run_group_tests(tests, nullptr, nullptr);
}
