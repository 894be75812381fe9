// The gripper board: the CRC-7 test vector, the firmware's parser directly,
// then the host driver over a real pseudo-terminal to the simulated board
// running the same firmware: safe start, calibration, a grasp on a
// handrail and an empty close, the serial timeout, corrupt packets and
// injected faults.
#include <chrono>
#include <cstring>
#include <thread>

#include "cmocka_cpp.hpp"
#include "gripper/gripper_board.hpp"
#include "gripper_fw.h"
#include "hal/linux_serial_port.hpp"
#include "sim_hal/sim_gripper.hpp"

namespace {

void test_crc7_vector_and_firmware_agree(void**) {
  const std::uint8_t v[4] = {0xD1, 0x01, 0x64, 0x00};
  assert_int_equal(gripper::crc7(v, 4), 0x68);
  assert_int_equal(gfw_crc7(v, 4), 0x68);
}

void test_firmware_parser_resynchronises(void**) {
  gfw_state s;
  gfw_init(&s, 0);
  // Garbage, a cut packet, then a valid GET_VERSION: only it is answered.
  const std::uint8_t junk[] = {0x12, 0x7F, 0x84, 0x05};
  for (std::uint8_t b : junk) gfw_receive(&s, b, 0, 1);
  assert_int_equal(s.tx_len, 0);
  std::uint8_t cmd = GFW_CMD_GET_VERSION;
  gfw_receive(&s, cmd, 0, 2);
  gfw_receive(&s, gfw_crc7(&cmd, 1), 0, 2);
  assert_int_equal(s.tx_len, 6);
  assert_int_equal(s.tx[0], GFW_CMD_GET_VERSION);
  assert_int_equal(s.tx[4], GFW_BOARD_ID);
  // A bad CRC: no reply, the CRC bit latched.
  s.tx_len = 0;
  gfw_receive(&s, cmd, 0, 3);
  gfw_receive(&s, static_cast<std::uint8_t>(gfw_crc7(&cmd, 1) ^ 1), 0, 3);
  assert_int_equal(s.tx_len, 0);
  assert_true(s.error & GFW_ERR_CRC);
  // An unknown command byte: format error.
  gfw_receive(&s, 0xF0, 0, 4);
  assert_true(s.error & GFW_ERR_FORMAT);
}

// The serial timeout compares times signed: a command stamped just after
// the tick that checks it (the UART and the tick read the clock apart) is
// not a timeout. The unsigned comparison tripped the simulated board now
// and then in hardware-in-loop runs.
void test_firmware_timeout_is_not_fooled_by_a_late_stamp(void**) {
  gfw_state s;
  gfw_init(&s, 0);
  const std::uint8_t cmd = GFW_CMD_EXIT_SAFE_START;
  gfw_receive(&s, cmd, 0, 1000);
  gfw_receive(&s, gfw_crc7(&cmd, 1), 0, 1000);
  assert_int_equal(s.safe_start, 0);
  gfw_tick(&s, 0, 0, 999);
  assert_false(s.error & GFW_ERR_TIMEOUT);
  assert_int_equal(s.safe_start, 0);
  gfw_tick(&s, 0, 0, 1000 + GFW_DEFAULT_TIMEOUT_MS + 1);
  assert_true(s.error & GFW_ERR_TIMEOUT);
  assert_int_equal(s.safe_start, 1);
}

struct Rig {
  sim_hal::SimGripperBoard board;
  hal::MonotonicClock clock;
  hal::LinuxSerialPort port;
  gripper::GripperBoard driver;
  // A reply timeout with room for a loaded host (the simulated board runs
  // in a thread of this process); replies meant to be late are far later.
  Rig() : driver(port, clock, 2, 150000) {
    std::string error;
    assert_true(board.start(&error));
    assert_int_equal(static_cast<int>(port.open(board.path(), 115200, &error)),
                     static_cast<int>(hal::SerialStatus::kOk));
  }
};

// Polls the state at 20 Hz (which also feeds the board's serial timeout)
// until `done` or the time runs out.
template <typename Done>
bool wait_for(Rig& rig, int timeout_ms, gripper::State* st, Done done) {
  for (int t = 0; t < timeout_ms; t += 50) {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    if (rig.driver.get_state(st) == gripper::Status::kOk && done(*st)) return true;
  }
  print_error(
      "gave up waiting: position %d, velocity %d, current %d mA, flags 0x%02x, error 0x%02x\n",
      st->position_counts, st->velocity_counts_s, st->current_ma, st->flags, st->error);
  return false;
}

void test_safe_start_calibrate_and_grasp(void**) {
  Rig rig;
  // Room in the serial timeout for a loaded host pausing this thread
  // between polls; the timeout has its own test below.
  assert_true(rig.driver.set_timeout_ms(2000) == gripper::Status::kOk);
  gripper::Version v;
  assert_int_equal(static_cast<int>(rig.driver.get_version(&v)),
                   static_cast<int>(gripper::Status::kOk));
  assert_int_equal(v.board_id, 0x42);
  assert_int_equal(v.protocol, 1);
  // Safe start: motion refused (answered, format error latched).
  gripper::State st;
  assert_true(rig.driver.get_state(&st) == gripper::Status::kOk);
  assert_true(st.has(gripper::kFlagSafeStart));
  assert_true(rig.driver.open(0.5) == gripper::Status::kOk);
  std::uint8_t err = 0;
  assert_true(rig.driver.get_error(&err) == gripper::Status::kOk);
  assert_true(err & gripper::kErrorFormat);
  assert_true(rig.driver.get_error(&err) == gripper::Status::kOk);
  assert_int_equal(err, 0);  // cleared by reading
  // GO_TO needs calibration.
  assert_true(rig.driver.exit_safe_start() == gripper::Status::kOk);
  assert_true(rig.driver.go_to(1000, 0.5) == gripper::Status::kOk);
  assert_true(rig.driver.get_error(&err) == gripper::Status::kOk);
  assert_true(err & gripper::kErrorNotCalibrated);
  // Calibrate: to the open stop, encoder zeroed there.
  assert_true(rig.driver.calibrate() == gripper::Status::kOk);
  assert_true(wait_for(rig, 8000, &st,
                       [](const gripper::State& s) { return s.has(gripper::kFlagCalibrated); }));
  assert_true(std::abs(st.position_counts) <= 5);
  // Close on a handrail 1800 counts from the open stop: holds there, at
  // the current limit.
  rig.board.set_handrail_raw(-500 + 1800);
  assert_true(rig.driver.close(0.6, 800) == gripper::Status::kOk);
  assert_true(wait_for(rig, 8000, &st,
                       [](const gripper::State& s) { return s.has(gripper::kFlagHolding); }));
  assert_true(std::abs(st.position_counts - 1800) <= 10);
  // The hold trims the drive down to the limit within a few tens of ms.
  assert_true(wait_for(rig, 1000, &st, [](const gripper::State& s) {
    return s.current_ma > 700 && s.current_ma < 900;
  }));
  assert_true(st.has(gripper::kFlagHolding));
  // Open again, then an empty close: it ends at the closed stop, which the
  // position tells apart from a handrail.
  rig.board.set_handrail_raw(-1);
  assert_true(rig.driver.open(1.0) == gripper::Status::kOk);
  assert_true(wait_for(rig, 8000, &st, [](const gripper::State& s) {
    return s.position_counts < 50 && !s.has(gripper::kFlagMoving);
  }));
  // Reversing while still closing (the handrail just taken away) must not
  // trip the over-current limit: the firmware ramps the drive.
  assert_false(st.error & gripper::kErrorOverCurrent);
  assert_true(rig.driver.close(0.6, 800) == gripper::Status::kOk);
  assert_true(wait_for(rig, 8000, &st, [](const gripper::State& s) {
    return s.has(gripper::kFlagHolding) || s.has(gripper::kFlagStalled);
  }));
  assert_true(st.position_counts > 2900);
  // GO_TO a position.
  assert_true(rig.driver.go_to(1000, 0.8) == gripper::Status::kOk);
  assert_true(wait_for(rig, 8000, &st, [](const gripper::State& s) {
    return std::abs(s.position_counts - 1000) <= 10 && !s.has(gripper::kFlagMoving);
  }));
}

void test_serial_timeout_stops_the_motor(void**) {
  Rig rig;
  assert_true(rig.driver.set_timeout_ms(200) == gripper::Status::kOk);
  assert_true(rig.driver.exit_safe_start() == gripper::Status::kOk);
  assert_true(rig.driver.open(0.3) == gripper::Status::kOk);
  std::this_thread::sleep_for(std::chrono::milliseconds(400));  // silence
  assert_int_equal(rig.board.snapshot().pwm, 0);
  gripper::State st;
  assert_true(rig.driver.get_state(&st) == gripper::Status::kOk);
  assert_true(st.has(gripper::kFlagSafeStart));
  assert_true(st.error & gripper::kErrorTimeout);
}

void test_faults_on_the_line(void**) {
  Rig rig;
  gripper::Version v;
  sim_hal::BusFaults f;
  f.no_reply = true;
  rig.board.set_faults(f);
  assert_int_equal(static_cast<int>(rig.driver.get_version(&v)),
                   static_cast<int>(gripper::Status::kTimeout));
  f = {};
  f.corrupt_checksum_probability = 1.0;
  rig.board.set_faults(f);
  assert_int_equal(static_cast<int>(rig.driver.get_version(&v)),
                   static_cast<int>(gripper::Status::kBadCrc));
  f.corrupt_checksum_probability = 0.3;
  rig.board.set_faults(f);
  int ok = 0;
  for (int k = 0; k < 20; ++k) ok += rig.driver.get_version(&v) == gripper::Status::kOk;
  assert_true(ok >= 17);
  f = {};
  f.drop_byte_probability = 0.05;
  rig.board.set_faults(f);
  ok = 0;
  for (int k = 0; k < 20; ++k) ok += rig.driver.get_version(&v) == gripper::Status::kOk;
  assert_true(ok >= 16);
  assert_true(rig.driver.retries_used() > 0);
  // Replies later than the driver waits: a timeout; the late bytes that
  // land afterwards are flushed before the next command.
  f = {};
  f.late_reply_us = 1000000;
  rig.board.set_faults(f);
  assert_int_equal(static_cast<int>(rig.driver.get_version(&v)),
                   static_cast<int>(gripper::Status::kTimeout));
  std::this_thread::sleep_for(std::chrono::milliseconds(1100));
  // A half-duplex line that echoes: the echoed command byte starts a packet
  // the reply parser ignores until the board's own reply.
  f = {};
  f.echo = true;
  rig.board.set_faults(f);
  assert_int_equal(static_cast<int>(rig.driver.get_version(&v)),
                   static_cast<int>(gripper::Status::kOk));
  assert_int_equal(v.board_id, 0x42);
  rig.board.set_faults({});
  assert_string_equal(gripper::error_bit_name(gripper::kErrorNotCalibrated), "NOT_CALIBRATED");
  assert_int_equal(static_cast<int>(rig.driver.close(0.5, 0)),
                   static_cast<int>(gripper::Status::kInvalidArgument));
}

}  // namespace

int main() {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_crc7_vector_and_firmware_agree),
      cmocka_unit_test(test_firmware_parser_resynchronises),
      cmocka_unit_test(test_firmware_timeout_is_not_fooled_by_a_late_stamp),
      cmocka_unit_test(test_safe_start_calibrate_and_grasp),
      cmocka_unit_test(test_serial_timeout_stops_the_motor),
      cmocka_unit_test(test_faults_on_the_line),
  };
  return cmocka_run_group_tests(tests, nullptr, nullptr);
}
