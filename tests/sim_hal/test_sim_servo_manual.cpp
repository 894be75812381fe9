// The simulated AX-12A against its manual, in real bytes over a pty:
//  - a packet with a wrong checksum is not carried out but answered with
//    the checksum error bit (0x10), as the manual's status packet says;
//  - EEPROM is writable with torque on; Lock (47) leaves only 24..35
//    writable (anything else: the range error bit, the manual's example
//    20) and only a power cycle clears it;
//  - a servo hears only its own Baud Rate (4), bps = 2,000,000 / (v + 1),
//    within a UART's 3 %, and a new rate applies after the reply to the
//    WRITE that set it.
#include <chrono>
#include <thread>

#include "cmocka_cpp.hpp"
#include "dynamixel/ax12.hpp"
#include "dynamixel/bus.hpp"
#include "dynamixel/protocol1.hpp"
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
    // A wide margin: the simulator's thread shares a possibly loaded host.
    // No retries: a silent servo is what some checks expect.
    dynamixel::BusConfig cfg;
    cfg.return_delay_us = 500;
    cfg.margin_us = 100000;
    cfg.retries = 0;
    bus.set_config(cfg);
  }
  // Sends raw bytes and collects what comes back within the time.
  std::size_t exchange(const std::uint8_t* tx, std::size_t n, std::uint8_t* rx, std::size_t cap,
                       std::size_t want, std::int64_t timeout_us) {
    port.flush_input();
    assert_int_equal(static_cast<int>(port.write(tx, n, 100000)),
                     static_cast<int>(hal::SerialStatus::kOk));
    std::size_t got = 0;
    port.read(rx, cap, want, &got, timeout_us);
    return got;
  }
};

void test_a_wrong_checksum_is_answered_with_the_checksum_bit(void**) {
  Rig rig;
  std::uint8_t rx[32];
  // PING ID 1: FF FF 01 02 01 FB; the checksum sent one off.
  const std::uint8_t bad_ping[] = {0xFF, 0xFF, 0x01, 0x02, 0x01, 0xFA};
  std::size_t n = rig.exchange(bad_ping, sizeof(bad_ping), rx, sizeof(rx), 6, 300000);
  // FF FF 01 02 10 EC: error 0x10, no parameters, its own checksum right.
  const std::uint8_t expect[] = {0xFF, 0xFF, 0x01, 0x02, 0x10, 0xEC};
  assert_int_equal(n, sizeof(expect));
  assert_memory_equal(rx, expect, sizeof(expect));

  // WRITE torque on (24 = 1) with a damaged checksum: refused the same
  // way, and not carried out.
  std::uint8_t write[dynamixel::kMaxPacket];
  const std::uint8_t params[2] = {ax12::kTorqueEnable, 1};
  const std::size_t wn =
      dynamixel::encode_instruction(1, dynamixel::Instruction::kWrite, params, 2, write);
  write[wn - 1] ^= 0x01;
  n = rig.exchange(write, wn, rx, sizeof(rx), 6, 300000);
  assert_int_equal(n, 6);
  assert_int_equal(rx[4], dynamixel::kErrorChecksum);
  std::this_thread::sleep_for(std::chrono::milliseconds(20));
  sim_hal::SimServo s;
  assert_true(rig.sim.servo(1, &s));
  assert_int_equal(s.table(ax12::kTorqueEnable), 0);

  // READ with a damaged checksum: the error bit and no data.
  const std::uint8_t read_params[2] = {ax12::kModelNumber, 2};
  std::uint8_t read[dynamixel::kMaxPacket];
  const std::size_t rn =
      dynamixel::encode_instruction(2, dynamixel::Instruction::kRead, read_params, 2, read);
  read[rn - 1] ^= 0x40;
  n = rig.exchange(read, rn, rx, sizeof(rx), 6, 300000);
  assert_int_equal(n, 6);
  assert_int_equal(rx[2], 2);  // from the ID addressed
  assert_int_equal(rx[3], 2);  // length: no parameters
  assert_int_equal(rx[4], dynamixel::kErrorChecksum);

  // A broadcast is never answered, damaged or not.
  const std::uint8_t bad_broadcast[] = {0xFF, 0xFF, 0xFE, 0x02, 0x01, 0x00};
  n = rig.exchange(bad_broadcast, sizeof(bad_broadcast), rx, sizeof(rx), 1, 200000);
  assert_int_equal(n, 0);

  // And an intact packet after all this is carried out as usual.
  assert_true(rig.bus.write_u8(1, ax12::kTorqueEnable, 1).ok());
}

void test_eeprom_with_torque_on_and_the_lock(void**) {
  Rig rig;
  ax12::Servo servo(rig.bus, 1);
  assert_true(servo.set_torque_enable(true).ok());
  // The AX-12A takes EEPROM writes with torque on.
  assert_true(rig.bus.write_u8(1, ax12::kReturnDelay, 50).ok());
  std::uint8_t v = 0;
  assert_true(rig.bus.read_u8(1, ax12::kReturnDelay, &v).ok());
  assert_int_equal(v, 50);

  // Lock on: the manual's example 20.
  assert_true(rig.bus.write_u8(1, ax12::kLock, 1).ok());
  dynamixel::BusResult r = rig.bus.write_u8(1, ax12::kReturnDelay, 60);
  assert_int_equal(static_cast<int>(r.status), static_cast<int>(BusStatus::kOk));
  assert_int_equal(r.servo_error, dynamixel::kErrorRange);
  r = rig.bus.write_u16(1, ax12::kCwAngleLimit, 100);
  assert_int_equal(r.servo_error, dynamixel::kErrorRange);
  r = rig.bus.write_u8(1, ax12::kId, 9);
  assert_int_equal(r.servo_error, dynamixel::kErrorRange);
  // Outside 24..35 in the RAM area too: Punch, as in the manual's example.
  r = rig.bus.write_u16(1, ax12::kPunch, 0x40);
  assert_int_equal(r.servo_error, dynamixel::kErrorRange);
  // 24..35 still take writes.
  assert_true(rig.bus.write_u16(1, ax12::kGoalPosition, 600).ok());
  assert_true(rig.bus.write_u16(1, ax12::kTorqueLimit, 800).ok());
  assert_true(rig.bus.write_u8(1, ax12::kLed, 1).ok());
  // The lock cannot be written off, nor reset away: RESET (FF FF 01 02 06
  // F6) would rewrite the EEPROM it guards and is refused (our reading: the
  // manual says only that a power cycle alone unlocks).
  r = rig.bus.write_u8(1, ax12::kLock, 0);
  assert_int_equal(r.servo_error, dynamixel::kErrorRange);
  const std::uint8_t reset[] = {0xFF, 0xFF, 0x01, 0x02, 0x06, 0xF6};
  std::uint8_t rx[16];
  assert_int_equal(rig.exchange(reset, sizeof(reset), rx, sizeof(rx), 6, 300000), 6);
  assert_int_equal(rx[4], dynamixel::kErrorRange);
  assert_true(rig.bus.read_u8(1, ax12::kLock, &v).ok());
  assert_int_equal(v, 1);
  assert_true(rig.bus.read_u8(1, ax12::kReturnDelay, &v).ok());
  assert_int_equal(v, 50);  // unchanged by the refused writes

  // A power cycle clears it; the EEPROM keeps what was written; the RAM
  // area starts over (torque off, torque limit from Max Torque).
  rig.sim.power_cycle(1);
  assert_true(rig.bus.read_u8(1, ax12::kLock, &v).ok());
  assert_int_equal(v, 0);
  assert_true(rig.bus.read_u8(1, ax12::kReturnDelay, &v).ok());
  assert_int_equal(v, 50);
  assert_true(rig.bus.read_u8(1, ax12::kTorqueEnable, &v).ok());
  assert_int_equal(v, 0);
  std::uint16_t limit = 0;
  assert_true(rig.bus.read_u16(1, ax12::kTorqueLimit, &limit).ok());
  assert_int_equal(limit, 1023);
  assert_true(rig.bus.write_u8(1, ax12::kReturnDelay, 250).ok());
  assert_true(rig.bus.write_u16(1, ax12::kPunch, 0x40).ok());
  // Lock takes 0 and 1 only.
  assert_int_equal(rig.bus.write_u8(1, ax12::kLock, 2).servo_error, dynamixel::kErrorRange);
}

void test_each_servo_hears_only_its_own_baud_rate(void**) {
  Rig rig;
  // The pty carries the rate the client set; the simulator reads it back.
  assert_int_equal(rig.sim.line_baud(), 1000000);
  assert_true(rig.bus.ping(1).ok());
  assert_int_equal(static_cast<int>(rig.port.set_baud(57600)),
                   static_cast<int>(hal::SerialStatus::kOk));
  assert_int_equal(rig.sim.line_baud(), 57600);
  assert_int_equal(static_cast<int>(rig.bus.ping(1).status), static_cast<int>(BusStatus::kTimeout));
  assert_int_equal(static_cast<int>(rig.bus.ping(2).status), static_cast<int>(BusStatus::kTimeout));

  // Servo 1 to 57,142.9 bps (value 34): the reply to that WRITE still
  // comes at 1 Mbps; from then on it hears only about 57,600.
  assert_int_equal(static_cast<int>(rig.port.set_baud(1000000)),
                   static_cast<int>(hal::SerialStatus::kOk));
  assert_true(rig.bus.write_u8(1, ax12::kBaudRate, 34).ok());
  assert_int_equal(static_cast<int>(rig.bus.ping(1).status), static_cast<int>(BusStatus::kTimeout));
  assert_true(rig.bus.ping(2).ok());  // servo 2 is still at 1 Mbps
  rig.port.set_baud(57600);           // 0.8 % off: understood
  assert_true(rig.bus.ping(1).ok());
  // Value 16 is 117,647 bps: a host at 115,200 (2.1 % off) is understood,
  // one at 57,600 no longer.
  assert_true(rig.bus.write_u8(1, ax12::kBaudRate, 16).ok());
  assert_int_equal(static_cast<int>(rig.bus.ping(1).status), static_cast<int>(BusStatus::kTimeout));
  rig.port.set_baud(115200);
  assert_true(rig.bus.ping(1).ok());
  assert_int_equal(static_cast<int>(rig.bus.ping(2).status), static_cast<int>(BusStatus::kTimeout));

  // A scan over the usual rates finds each servo once, at its own rate.
  const std::uint32_t bauds[] = {1000000, 115200, 57600};
  ax12::ScanHit hits[8];
  const std::size_t n = ax12::scan(rig.bus, bauds, 3, 0, 3, hits, 8);
  assert_int_equal(n, 2);
  assert_int_equal(hits[0].id, 2);
  assert_int_equal(hits[0].baud, 1000000);
  assert_int_equal(hits[1].id, 1);
  assert_int_equal(hits[1].baud, 115200);
}

}  // namespace

int main() {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_a_wrong_checksum_is_answered_with_the_checksum_bit),
      cmocka_unit_test(test_eeprom_with_torque_on_and_the_lock),
      cmocka_unit_test(test_each_servo_hears_only_its_own_baud_rate),
  };
  return cmocka_run_group_tests(tests, nullptr, nullptr);
}
