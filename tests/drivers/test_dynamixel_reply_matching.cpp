// Which reply the bus takes for which instruction, against simulated
// AX-12A servos on a real pty. Protocol 1.0 status packets carry no
// transaction number: a reply that comes after its timeout was taken by an
// SDK client as the answer to its next read. Here late replies are made on
// purpose (the simulator's late-reply fault) and the next transaction must
// get its own reply, with the stale one counted and discarded:
//  - a stale reply landing inside the next transaction's window;
//  - a stale reply already waiting when the next transaction starts;
//  - stray replies of another ID or another length inside a window;
//  - a damaged instruction, answered with the checksum error bit: retried.
#include <chrono>
#include <cstring>
#include <thread>

#include "cmocka_cpp.hpp"
#include "dynamixel/ax12.hpp"
#include "dynamixel/bus.hpp"
#include "hal/linux_serial_port.hpp"
#include "sim_hal/sim_servo_bus.hpp"

using dynamixel::BusStatus;
namespace ax12 = dynamixel::ax12;

namespace {

// The real port, with the checksum of the next `corrupt` instructions
// damaged on the way out (noise on the line, which a pty does not have).
class DamagingPort final : public hal::SerialPort {
 public:
  explicit DamagingPort(hal::SerialPort& port) : port_(port) {}
  int corrupt = 0;
  hal::SerialStatus write(const std::uint8_t* data, std::size_t n,
                          std::int64_t timeout_us) override {
    if (corrupt <= 0 || n == 0 || n > sizeof(buf_)) return port_.write(data, n, timeout_us);
    --corrupt;
    std::memcpy(buf_, data, n);
    buf_[n - 1] ^= 0x21;
    return port_.write(buf_, n, timeout_us);
  }
  hal::SerialStatus read(std::uint8_t* out, std::size_t capacity, std::size_t min_bytes,
                         std::size_t* n_read, std::int64_t timeout_us) override {
    return port_.read(out, capacity, min_bytes, n_read, timeout_us);
  }
  hal::SerialStatus flush_input() override { return port_.flush_input(); }
  hal::SerialStatus set_baud(std::uint32_t baud) override { return port_.set_baud(baud); }
  std::uint32_t baud() const override { return port_.baud(); }
  void set_echo_suppression(bool on) override { port_.set_echo_suppression(on); }

 private:
  hal::SerialPort& port_;
  std::uint8_t buf_[dynamixel::kMaxPacket];
};

// Timing of the late-reply cases, from the bus's reply timeout T (about
// 300 ms, wide for a loaded host): a stale reply L1 = T + 100 ms after its
// instruction misses its own window and, without the quiet time, would land
// in the next one, whose own reply is L2 = 200 ms late (100 ms after the
// stale one). Each event is 100 ms from the next.
constexpr std::uint32_t kMarginUs = 300000;

struct Rig {
  sim_hal::SimServoBus sim;
  hal::MonotonicClock clock;
  hal::LinuxSerialPort serial;
  DamagingPort port{serial};
  dynamixel::Bus bus;
  Rig() : bus(port, clock) {
    std::string error;
    assert_true(sim.start(&error));
    assert_int_equal(static_cast<int>(serial.open(sim.path(), 1000000, &error)),
                     static_cast<int>(hal::SerialStatus::kOk));
    dynamixel::BusConfig cfg;
    cfg.return_delay_us = 500;
    cfg.margin_us = kMarginUs;
    cfg.retries = 0;  // one attempt per transaction: the timing stays plain
    bus.set_config(cfg);
    // A goal unlike the model number (12): whose reply was taken shows.
    assert_true(bus.write_u16(1, ax12::kGoalPosition, 700).ok());
  }
  std::int64_t read_timeout_us() const { return bus.reply_timeout_us(8, 8); }
  void late(std::uint32_t us) {
    sim_hal::BusFaults f;
    f.late_reply_us = us;
    sim.set_faults(f);
  }
};

void test_a_stale_reply_inside_the_next_window_is_not_taken(void**) {
  Rig rig;
  const std::int64_t t = rig.read_timeout_us();
  rig.late(static_cast<std::uint32_t>(t + 100000));
  std::uint16_t model = 0;
  const dynamixel::BusResult r1 = rig.bus.read_u16(1, ax12::kModelNumber, &model);
  assert_int_equal(static_cast<int>(r1.status), static_cast<int>(BusStatus::kTimeout));
  // The next READ, same ID, same length: its own reply comes 100 ms after
  // the stale one would have been taken.
  rig.late(200000);
  std::uint16_t goal = 0;
  const dynamixel::BusResult r2 = rig.bus.read_u16(1, ax12::kGoalPosition, &goal);
  if (!r2.ok()) print_error("second read: %s\n", dynamixel::to_string(r2.status));
  assert_true(r2.ok());
  assert_int_equal(goal, 700);  // its own, never the model number (12)
  assert_int_equal(rig.bus.counters().stale_replies, 1);
  // Nothing left over for later: a third read gets its own reply at once.
  rig.late(0);
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  assert_true(rig.bus.read_u16(1, ax12::kModelNumber, &model).ok());
  assert_int_equal(model, ax12::kModelAx12A);
  assert_int_equal(rig.bus.counters().stale_replies, 1);
}

void test_a_stale_reply_waiting_at_the_start_is_discarded(void**) {
  Rig rig;
  const std::int64_t t = rig.read_timeout_us();
  rig.late(static_cast<std::uint32_t>(t + 100000));
  std::uint16_t value = 0;
  assert_int_equal(static_cast<int>(rig.bus.read_u16(1, ax12::kModelNumber, &value).status),
                   static_cast<int>(BusStatus::kTimeout));
  rig.late(0);
  // Long enough for the stale reply to have arrived and the quiet time to
  // be over: it sits in the port's buffer when the next READ starts.
  std::this_thread::sleep_for(std::chrono::microseconds(t + 300000));
  const std::uint32_t before = rig.bus.counters().stale_replies;
  assert_true(rig.bus.read_u16(1, ax12::kGoalPosition, &value).ok());
  assert_int_equal(value, 700);
  assert_int_equal(rig.bus.counters().stale_replies, before + 1);
}

void test_stray_replies_of_another_id_or_length_are_not_taken(void**) {
  Rig rig;
  // The bus believes writes go unanswered (status return level 1) while
  // the servos still answer them (level 2): each WRITE leaves a reply on
  // the line that nobody waits for, here 100 ms late, so that it arrives
  // inside the READ's window just before the READ's own reply.
  dynamixel::BusConfig cfg = rig.bus.config();
  cfg.status_return_level = 1;
  rig.bus.set_config(cfg);
  rig.late(100000);
  std::uint16_t goal = 0;
  // Another servo's reply (ID 2, no parameters) during a READ of ID 1.
  assert_int_equal(static_cast<int>(rig.bus.write_u8(2, ax12::kLed, 1).status),
                   static_cast<int>(BusStatus::kOk));
  dynamixel::BusResult r = rig.bus.read_u16(1, ax12::kGoalPosition, &goal);
  assert_true(r.ok());
  assert_int_equal(goal, 700);
  assert_int_equal(rig.bus.counters().wrong_replies, 1);
  // The same servo's reply of another length (a WRITE's: no parameters)
  // during a READ of two bytes.
  assert_int_equal(static_cast<int>(rig.bus.write_u8(1, ax12::kLed, 1).status),
                   static_cast<int>(BusStatus::kOk));
  goal = 0;
  r = rig.bus.read_u16(1, ax12::kGoalPosition, &goal);
  assert_true(r.ok());
  assert_int_equal(goal, 700);
  assert_int_equal(rig.bus.counters().wrong_replies, 2);
  // And a READ of one byte is not answered by a two-byte status.
  std::uint8_t led = 0;
  assert_true(rig.bus.read_u8(1, ax12::kLed, &led).ok());
  assert_int_equal(led, 1);
  assert_int_equal(rig.bus.counters().stale_replies, 0);
}

void test_a_damaged_instruction_is_retried(void**) {
  Rig rig;
  dynamixel::BusConfig cfg = rig.bus.config();
  cfg.retries = 2;
  rig.bus.set_config(cfg);
  // The servo answers a damaged PING with the checksum bit: tried again,
  // and the second, intact, attempt answers.
  rig.port.corrupt = 1;
  dynamixel::BusResult r = rig.bus.ping(1);
  assert_true(r.ok());
  assert_int_equal(rig.bus.counters().instruction_checksum_errors, 1);
  assert_int_equal(rig.bus.counters().retries, 1);
  // A damaged WRITE is not carried out; its retry is.
  rig.port.corrupt = 1;
  assert_true(rig.bus.write_u8(1, ax12::kLed, 1).ok());
  std::uint8_t led = 0;
  assert_true(rig.bus.read_u8(1, ax12::kLed, &led).ok());
  assert_int_equal(led, 1);
  // A damaged READ: the servo's refusal carries no data and is not taken
  // for the bytes asked; the retry's reply is.
  rig.port.corrupt = 1;
  std::uint16_t goal = 0;
  assert_true(rig.bus.read_u16(1, ax12::kGoalPosition, &goal).ok());
  assert_int_equal(goal, 700);
  // Damaged every time: the result says so (the servo's checksum bit).
  rig.port.corrupt = 3;
  r = rig.bus.ping(1);
  assert_int_equal(static_cast<int>(r.status), static_cast<int>(BusStatus::kOk));
  assert_int_equal(r.servo_error, dynamixel::kErrorChecksum);
  rig.port.corrupt = 3;
  r = rig.bus.read_u16(1, ax12::kGoalPosition, &goal);
  assert_int_equal(static_cast<int>(r.status), static_cast<int>(BusStatus::kWrongReply));
  assert_true(r.servo_error & dynamixel::kErrorChecksum);
}

}  // namespace

int main() {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_a_stale_reply_inside_the_next_window_is_not_taken),
      cmocka_unit_test(test_a_stale_reply_waiting_at_the_start_is_discarded),
      cmocka_unit_test(test_stray_replies_of_another_id_or_length_are_not_taken),
      cmocka_unit_test(test_a_damaged_instruction_is_retried),
  };
  return cmocka_run_group_tests(tests, nullptr, nullptr);
}
