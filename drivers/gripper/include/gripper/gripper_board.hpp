#pragma once
// The host's side of the gripper board protocol (drivers/gripper/PROTOCOL.md):
// one command out, its reply back, CRC-7 checked, with a timeout worked out
// from the baud rate and a bounded number of retries. No allocation, no
// exceptions.
#include <cstddef>
#include <cstdint>

#include "hal/clock.hpp"
#include "hal/serial_port.hpp"

namespace gripper {

enum class Status : std::uint8_t {
  kOk,
  kTimeout,          // no reply (the board is off, or refused a corrupt packet)
  kBadCrc,           // only corrupt replies
  kSerialError,      // the port failed
  kInvalidArgument,  // a value the protocol cannot carry
};
const char* to_string(Status status);

enum Flag : std::uint8_t {
  kFlagCalibrated = 1u << 0,
  kFlagMoving = 1u << 1,
  kFlagHolding = 1u << 2,
  kFlagStalled = 1u << 3,
  kFlagOverCurrent = 1u << 4,
  kFlagSafeStart = 1u << 5,
  kFlagError = 1u << 6,
};

enum ErrorBit : std::uint8_t {
  kErrorFraming = 1u << 0,
  kErrorOverrun = 1u << 1,
  kErrorCrc = 1u << 2,
  kErrorFormat = 1u << 3,
  kErrorTimeout = 1u << 4,
  kErrorOverCurrent = 1u << 5,
  kErrorNotCalibrated = 1u << 6,
};
// The name of one error bit ("CRC", ...); "NONE" for 0.
const char* error_bit_name(std::uint8_t bit);

struct Version {
  std::uint8_t protocol = 0, major = 0, minor = 0, board_id = 0;
};

struct State {
  int position_counts = 0;  // from the open stop (after calibration)
  int velocity_counts_s = 0;
  int current_ma = 0;
  std::uint8_t flags = 0;  // Flag bits
  std::uint8_t error = 0;  // ErrorBit bits, latched on the board
  bool has(Flag f) const { return (flags & f) != 0; }
};

std::uint8_t crc7(const std::uint8_t* bytes, std::size_t n);

// Byte-at-a-time reply parser: resynchronises on any command byte.
class ReplyParser {
 public:
  enum class Event : std::uint8_t { kNone, kReply, kBadCrc };
  // Expects the reply to `command` (its data length is known from it).
  void expect(std::uint8_t command);
  Event push(std::uint8_t byte);
  const std::uint8_t* data() const { return data_; }
  std::size_t size() const { return n_; }

 private:
  std::uint8_t command_ = 0, want_ = 0, n_ = 0;
  bool in_packet_ = false;
  std::uint8_t data_[16] = {};
};

class GripperBoard {
 public:
  GripperBoard(hal::SerialPort& port, const hal::Clock& clock, std::uint8_t retries = 2,
               std::uint32_t margin_us = 5000);

  Status get_version(Version* version);
  Status exit_safe_start();
  Status open(double speed_fraction);
  Status close(double speed_fraction, int current_limit_ma);
  Status stop();
  Status go_to(int position_counts, double speed_fraction);
  Status calibrate();
  Status get_state(State* state);
  // Reads and clears the latched error byte. Not retried: a lost reply
  // would have cleared it already.
  Status get_error(std::uint8_t* error);
  Status set_timeout_ms(int timeout_ms);

  void set_margin_us(std::uint32_t margin_us) { margin_us_ = margin_us; }
  std::uint32_t retries_used() const { return retries_used_; }

 private:
  Status transact(std::uint8_t command, const std::uint8_t* data, std::size_t n,
                  std::uint8_t* reply, std::size_t reply_n, std::uint8_t retries);

  hal::SerialPort& port_;
  const hal::Clock& clock_;
  std::uint8_t retries_;
  std::uint32_t margin_us_;
  std::uint32_t retries_used_ = 0;
  ReplyParser parser_;
};

}  // namespace gripper
