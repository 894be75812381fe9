// The Dynamixel driver, unchanged, against simulated AX-12A servos served
// on a real pseudo-terminal: normal operation, the control table's rules,
// every injected fault, alarm recovery, a scan, and no allocation in the
// bus's steady state.
#include <chrono>
#include <cmath>
#include <thread>

#include "allocation_counter.hpp"
#include "cmocka_cpp.hpp"
#include "dynamixel/ax12.hpp"
#include "dynamixel/bus.hpp"
#include "hal/linux_serial_port.hpp"
#include "sim_hal/sim_servo_bus.hpp"

using dynamixel::BusStatus;
namespace ax12 = dynamixel::ax12;

namespace {

struct Rig {
  sim_hal::SimServoBus sim;
  hal::MonotonicClock clock;
  hal::LinuxSerialPort port;
  dynamixel::Bus bus;
  Rig() : bus(port, clock) {
    std::string error;
    assert_true(sim.start(&error));
    assert_int_equal(static_cast<int>(port.open(sim.path(), 1000000, &error)),
                     static_cast<int>(hal::SerialStatus::kOk));
    // The servos' default return delay is 500 us. The simulator's thread
    // shares the host with the test, and on a shared virtual machine both
    // can stall for hundreds of ms: a generous margin keeps scheduling
    // delays from reading as lost replies (the retries are tested apart).
    dynamixel::BusConfig cfg;
    cfg.return_delay_us = 500;
    cfg.margin_us = 150000;
    bus.set_config(cfg);
  }
};

void test_ping_read_write_move(void**) {
  Rig rig;
  assert_true(rig.bus.ping(1).ok());
  assert_true(rig.bus.ping(2).ok());
  std::uint16_t model = 0;
  assert_true(rig.bus.read_u16(1, ax12::kModelNumber, &model).ok());
  assert_int_equal(model, ax12::kModelAx12A);
  // Nobody at ID 7: a timeout after the retries, within the worked-out time.
  hal::MonotonicClock clock;
  const std::int64_t t0 = clock.now_us();
  const dynamixel::BusResult missing = rig.bus.ping(7);
  assert_int_equal(static_cast<int>(missing.status), static_cast<int>(BusStatus::kTimeout));
  // Bounded: three attempts, each its reply timeout (room left for a stall).
  assert_true(clock.now_us() - t0 < 3 * rig.bus.reply_timeout_us(6, 6) + 300000);

  ax12::Servo servo(rig.bus, 1);
  assert_true(servo.set_moving_speed(3.0).ok());
  assert_true(servo.set_torque_enable(true).ok());
  assert_true(servo.set_goal_position(0.5).ok());
  ax12::ServoState state;
  bool arrived = false;
  for (int k = 0; k < 400 && !arrived; ++k) {
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
    assert_true(servo.read_state(&state).ok());
    arrived = std::fabs(state.position_rad - 0.5) < 0.01 && !state.moving;
  }
  assert_true(arrived);
  assert_near(state.voltage_v, 12.0, 0.05);
  assert_true(state.temperature_c >= 25 && state.temperature_c <= 40);
}

void test_control_table_rules(void**) {
  Rig rig;
  ax12::Servo servo(rig.bus, 2);
  assert_true(servo.set_torque_enable(true).ok());
  // The AX-12A writes its EEPROM with torque on too (its lock is Lock,
  // address 47: tests/sim_hal/test_sim_servo_manual.cpp).
  dynamixel::BusResult r = rig.bus.write_u8(2, ax12::kReturnDelay, 10);
  assert_int_equal(static_cast<int>(r.status), static_cast<int>(BusStatus::kOk));
  assert_int_equal(r.servo_error, 0);
  assert_true(servo.set_torque_enable(false).ok());
  assert_true(rig.bus.write_u16(2, ax12::kCwAngleLimit, 400).ok());
  assert_true(rig.bus.write_u16(2, ax12::kCcwAngleLimit, 600).ok());
  // A goal outside the angle limits is refused.
  r = rig.bus.write_u16(2, ax12::kGoalPosition, 700);
  assert_true(r.servo_error & dynamixel::kErrorAngleLimit);
  // REG_WRITE waits for ACTION.
  assert_true(rig.bus.write_u8(2, ax12::kTorqueEnable, 1).ok());
  const std::uint8_t goal[2] = {0x2C, 0x01};  // 300
  assert_true(rig.bus.reg_write(2, ax12::kGoalPosition, goal, 2).servo_error &
                      dynamixel::kErrorAngleLimit
                  ? false
                  : true);
  std::uint8_t registered = 0;
  assert_true(rig.bus.read_u8(2, ax12::kRegistered, &registered).ok());
  assert_int_equal(registered, 1);
  assert_true(rig.bus.action().status == BusStatus::kOk);
  std::this_thread::sleep_for(std::chrono::milliseconds(5));
  assert_true(rig.bus.read_u8(2, ax12::kRegistered, &registered).ok());
  assert_int_equal(registered, 0);
  // SYNC_WRITE: both goals in one packet, no reply.
  assert_true(rig.bus.write_u8(1, ax12::kTorqueEnable, 1).ok());
  const std::uint8_t ids[2] = {1, 2};
  const std::uint8_t goals[4] = {0x20, 0x02, 0xF4, 0x01};  // 544, 500
  assert_true(rig.bus.sync_write(ax12::kGoalPosition, 2, ids, goals, 2).status == BusStatus::kOk);
  std::this_thread::sleep_for(std::chrono::milliseconds(5));
  std::uint16_t g1 = 0, g2 = 0;
  assert_true(rig.bus.read_u16(1, ax12::kGoalPosition, &g1).ok());
  assert_true(rig.bus.read_u16(2, ax12::kGoalPosition, &g2).ok());
  assert_int_equal(g1, 544);
  assert_int_equal(g2, 500);
  // Status return level 1: writes go unanswered (this one already, as the
  // servo applies it before answering), reads still answer.
  assert_true(servo.set_torque_enable(false).ok());
  dynamixel::BusConfig cfg = rig.bus.config();
  cfg.status_return_level = 1;
  rig.bus.set_config(cfg);
  assert_true(rig.bus.write_u8(2, ax12::kStatusReturnLevel, 1).status == BusStatus::kOk);
  assert_true(rig.bus.write_u8(2, ax12::kLed, 1).status == BusStatus::kOk);
  std::uint8_t led = 0;
  assert_true(rig.bus.read_u8(2, ax12::kLed, &led).ok());
  assert_int_equal(led, 1);
}

void test_injected_faults(void**) {
  Rig rig;
  sim_hal::BusFaults f;
  // Every reply corrupted: reported as such after the retries.
  f.corrupt_checksum_probability = 1.0;
  rig.sim.set_faults(f);
  dynamixel::BusResult r = rig.bus.ping(1);
  assert_int_equal(static_cast<int>(r.status), static_cast<int>(BusStatus::kBadChecksum));
  // One in three corrupted: the retries hide it.
  f.corrupt_checksum_probability = 0.3;
  rig.sim.set_faults(f);
  int ok = 0;
  for (int k = 0; k < 30; ++k) ok += rig.bus.ping(1).ok();
  assert_true(ok >= 27);
  assert_true(rig.bus.counters().retries > 0);
  // Dropped bytes: the parser resynchronises on the next packet.
  f = {};
  f.drop_byte_probability = 0.05;
  rig.sim.set_faults(f);
  ok = 0;
  for (int k = 0; k < 30; ++k) ok += rig.bus.ping(2).ok();
  assert_true(ok >= 25);
  // No reply, and a reply later than the timeout: timeouts.
  f = {};
  f.no_reply = true;
  rig.sim.set_faults(f);
  assert_int_equal(static_cast<int>(rig.bus.ping(1).status), static_cast<int>(BusStatus::kTimeout));
  f = {};
  f.late_reply_us = 1000000;  // later than all three attempts together
  rig.sim.set_faults(f);
  assert_int_equal(static_cast<int>(rig.bus.ping(1).status), static_cast<int>(BusStatus::kTimeout));
  // Let the late replies land before going on.
  std::this_thread::sleep_for(std::chrono::milliseconds(1000));
  // Echo: without suppression the echoed READ parses as a status packet
  // (the maker's SDK pitfall); with it, the reply is the servo's.
  f = {};
  f.echo = true;
  rig.sim.set_faults(f);
  std::uint16_t model = 0;
  r = rig.bus.read_u16(1, ax12::kModelNumber, &model);
  assert_true(r.servo_error == dynamixel::kErrorAngleLimit || model != ax12::kModelAx12A);
  rig.port.set_echo_suppression(true);
  model = 0;
  r = rig.bus.read_u16(1, ax12::kModelNumber, &model);
  if (!r.ok()) {
    print_error("status %s error 0x%x serial %s\n", dynamixel::to_string(r.status), r.servo_error,
                hal::to_string(r.serial_status));
  }
  assert_true(r.ok());
  assert_int_equal(model, ax12::kModelAx12A);
  rig.port.set_echo_suppression(false);
  rig.sim.set_faults({});
  // Overload and overheating bits: reported, and the alarm shutdown drops
  // the torque limit; recovery restores it once the cause is gone.
  ax12::Servo servo(rig.bus, 1);
  assert_true(servo.set_torque_enable(true).ok());
  rig.sim.force_error_bits(1, dynamixel::kErrorOverload);
  std::this_thread::sleep_for(std::chrono::milliseconds(10));
  r = rig.bus.ping(1);
  assert_true(r.servo_error & dynamixel::kErrorOverload);
  std::uint16_t limit = 1;
  rig.bus.read_u16(1, ax12::kTorqueLimit, &limit);
  assert_int_equal(limit, 0);
  r = servo.recover_from_alarm();  // cause still there: refuses
  assert_true(r.servo_error & dynamixel::kErrorOverload);
  rig.sim.force_error_bits(1, 0);
  std::this_thread::sleep_for(std::chrono::milliseconds(10));
  assert_true(servo.recover_from_alarm().ok());
  assert_true(rig.bus.read_u16(1, ax12::kTorqueLimit, &limit).ok());
  assert_int_equal(limit, 1023);
  rig.sim.force_error_bits(2, dynamixel::kErrorOverheating);
  std::this_thread::sleep_for(std::chrono::milliseconds(10));
  assert_true(rig.bus.ping(2).servo_error & dynamixel::kErrorOverheating);
}

void test_scan_finds_the_servos(void**) {
  Rig rig;
  const std::uint32_t bauds[] = {1000000, 57600};
  ax12::ScanHit hits[8];
  const std::size_t n = ax12::scan(rig.bus, bauds, 2, 0, 4, hits, 8);
  // Each servo answers only at its own rate (1 Mbps), as on a real line.
  assert_int_equal(n, 2);
  assert_int_equal(hits[0].id, 1);
  assert_int_equal(hits[1].id, 2);
  assert_int_equal(hits[0].baud, 1000000);
  assert_int_equal(hits[1].baud, 1000000);
  assert_int_equal(hits[0].model, ax12::kModelAx12A);
  assert_int_equal(rig.bus.config().retries, 2);  // restored
}

void test_no_allocation_in_steady_state(void**) {
  Rig rig;
  ax12::Servo servo(rig.bus, 1);
  ax12::ServoState state;
  assert_true(servo.read_state(&state).ok());  // warm up
  alloc_counter::arm();
  for (int k = 0; k < 300; ++k) {
    servo.read_state(&state);
    servo.set_goal_position(0.1 * (k % 5));
    rig.bus.ping(2);
  }
  assert_int_equal(alloc_counter::disarm(), 0);
}

}  // namespace

int main() {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_ping_read_write_move),
      cmocka_unit_test(test_control_table_rules),
      cmocka_unit_test(test_injected_faults),
      cmocka_unit_test(test_scan_finds_the_servos),
      cmocka_unit_test(test_no_allocation_in_steady_state),
  };
  return cmocka_run_group_tests(tests, nullptr, nullptr);
}
