// The simulated AX-12A's rules and motion model, as pure logic with time
// passed in: speed limit and the moving flag, heating under load, an
// overload that latches and shuts the torque down, and the recovery.
#include <cmath>

#include "cmocka_cpp.hpp"
#include "dynamixel/protocol1.hpp"
#include "sim_hal/sim_servo.hpp"

using sim_hal::SimServo;

namespace {

std::uint8_t write(SimServo& s, std::uint8_t address, std::uint16_t value, std::size_t n) {
  const std::uint8_t params[3] = {address, static_cast<std::uint8_t>(value & 0xFF),
                                  static_cast<std::uint8_t>(value >> 8)};
  const dynamixel::InstructionPacket p{s.id(), 0x03, static_cast<std::uint8_t>(n + 1), params};
  std::uint8_t error = 0, out[8];
  std::size_t n_out = 0;
  s.handle(p, &error, out, &n_out);
  return error;
}

void test_moves_at_the_commanded_speed(void**) {
  SimServo s(1);
  assert_int_equal(write(s, 24, 1, 1), 0);    // torque on
  assert_int_equal(write(s, 32, 100, 2), 0);  // 100 units = 11.1 rpm = 1.162 rad/s
  assert_int_equal(write(s, 30, 712, 2), 0);  // +200 units = 1.0 rad
  s.step(0.5, 0.0);
  assert_near(s.position_rad(), 0.5 * 1.162, 0.01);
  assert_int_equal(s.table(46), 1);  // moving
  for (int k = 0; k < 100; ++k) s.step(0.01, 0.0);
  assert_near(s.position_rad(), 200 * 300.0 / 1023.0 * M_PI / 180.0, 0.005);
  assert_int_equal(s.table(46), 0);
}

void test_heats_under_load_and_shuts_down_on_overload(void**) {
  SimServo s(2);
  write(s, 24, 1, 1);
  const double t0 = s.temperature_c();
  // Holding 70 % of the stall torque for 10 s warms it (not yet to the
  // 70 C limit, which would shut it down for overheating).
  for (int k = 0; k < 100; ++k) s.step(0.1, 0.7 * 1.5);
  assert_true(s.temperature_c() > t0 + 10.0 && s.temperature_c() < 70.0);
  assert_false(s.error_bits() & dynamixel::kErrorOverheating);
  assert_true(s.table16(40) > 600);  // present load
  // More than it can give: an overload that latches and drops the torque
  // limit (alarm shutdown).
  for (int k = 0; k < 10; ++k) s.step(0.1, 2.0);
  assert_true(s.error_bits() & dynamixel::kErrorOverload);
  assert_int_equal(s.table16(34), 0);
  // The cause still there: writing the torque limit does not clear it.
  write(s, 34, 1023, 2);
  assert_true(s.error_bits() & dynamixel::kErrorOverload);
  // Cause gone: it does.
  s.step(0.1, 0.0);
  write(s, 34, 1023, 2);
  assert_false(s.error_bits() & dynamixel::kErrorOverload);
  assert_int_equal(s.table16(34), 1023);
}

}  // namespace

int main() {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_moves_at_the_commanded_speed),
      cmocka_unit_test(test_heats_under_load_and_shuts_down_on_overload),
  };
  return cmocka_run_group_tests(tests, nullptr, nullptr);
}
