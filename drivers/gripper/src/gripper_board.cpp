#include "gripper/gripper_board.hpp"

#include <cmath>
#include <cstring>

namespace gripper {
namespace {

// Reply data bytes per command (the protocol's table).
std::uint8_t reply_length(std::uint8_t command) {
  switch (command) {
    case 0x81:
      return 4;
    case 0x88:
      return 8;
    case 0x89:
      return 1;
    default:
      return 0;
  }
}

int from14(const std::uint8_t* d, bool is_signed) {
  int v = d[0] | (d[1] << 7);
  if (is_signed && (v & 0x2000)) v -= 0x4000;
  return v;
}

std::uint8_t speed_byte(double fraction) {
  const double v = std::round(fraction * 127.0);
  if (!(v >= 0.0)) return 0;
  return static_cast<std::uint8_t>(v > 127.0 ? 127.0 : v);
}

}  // namespace

const char* to_string(Status status) {
  switch (status) {
    case Status::kOk:
      return "OK";
    case Status::kTimeout:
      return "TIMEOUT";
    case Status::kBadCrc:
      return "BAD_CRC";
    case Status::kSerialError:
      return "SERIAL_ERROR";
    case Status::kInvalidArgument:
      return "INVALID_ARGUMENT";
  }
  return "UNKNOWN";
}

const char* error_bit_name(std::uint8_t bit) {
  switch (bit) {
    case 0:
      return "NONE";
    case kErrorFraming:
      return "FRAMING";
    case kErrorOverrun:
      return "OVERRUN";
    case kErrorCrc:
      return "CRC";
    case kErrorFormat:
      return "FORMAT";
    case kErrorTimeout:
      return "SERIAL_TIMEOUT";
    case kErrorOverCurrent:
      return "OVER_CURRENT";
    case kErrorNotCalibrated:
      return "NOT_CALIBRATED";
    default:
      return "UNKNOWN";
  }
}

std::uint8_t crc7(const std::uint8_t* bytes, std::size_t n) {
  std::uint8_t crc = 0;
  for (std::size_t i = 0; i < n; ++i) {
    crc ^= bytes[i];
    for (int b = 0; b < 8; ++b) {
      if (crc & 1) crc ^= 0x91;
      crc >>= 1;
    }
  }
  return crc & 0x7F;
}

void ReplyParser::expect(std::uint8_t command) {
  command_ = command;
  want_ = reply_length(command);
  n_ = 0;
  in_packet_ = false;
}

ReplyParser::Event ReplyParser::push(std::uint8_t byte) {
  if (byte & 0x80) {
    // A command byte starts a packet; only the awaited command's counts.
    in_packet_ = byte == command_;
    n_ = 0;
    return Event::kNone;
  }
  if (!in_packet_) return Event::kNone;
  if (n_ < want_) {
    data_[n_++] = byte;
    return Event::kNone;
  }
  in_packet_ = false;
  std::uint8_t packet[1 + sizeof(data_)];
  packet[0] = command_;
  std::memcpy(packet + 1, data_, n_);
  return crc7(packet, 1u + n_) == byte ? Event::kReply : Event::kBadCrc;
}

GripperBoard::GripperBoard(hal::SerialPort& port, const hal::Clock& clock, std::uint8_t retries,
                           std::uint32_t margin_us)
    : port_(port), clock_(clock), retries_(retries), margin_us_(margin_us) {}

Status GripperBoard::transact(std::uint8_t command, const std::uint8_t* data, std::size_t n,
                              std::uint8_t* reply, std::size_t reply_n, std::uint8_t retries) {
  std::uint8_t tx[8];
  tx[0] = command;
  for (std::size_t k = 0; k < n; ++k) tx[1 + k] = data[k];
  tx[1 + n] = crc7(tx, 1 + n);
  const std::size_t tx_n = n + 2;
  const std::uint32_t baud = port_.baud() ? port_.baud() : 115200u;
  const std::int64_t wire_us =
      static_cast<std::int64_t>((tx_n + reply_n + 2) * 10u * 1000000u / baud) + 1;
  Status result = Status::kTimeout;
  for (unsigned attempt = 0; attempt <= retries; ++attempt) {
    if (attempt > 0) ++retries_used_;
    port_.flush_input();
    const std::int64_t deadline = clock_.now_us() + wire_us + margin_us_;
    if (port_.write(tx, tx_n, wire_us + margin_us_) != hal::SerialStatus::kOk) {
      return Status::kSerialError;
    }
    parser_.expect(command);
    result = Status::kTimeout;
    std::uint8_t rx[32];
    for (int pass = 0; pass < 64; ++pass) {
      const std::int64_t left = deadline - clock_.now_us();
      if (left <= 0) break;
      std::size_t got = 0;
      const hal::SerialStatus s = port_.read(rx, sizeof(rx), 1, &got, left);
      if (s == hal::SerialStatus::kTimeout) break;
      if (s != hal::SerialStatus::kOk) return Status::kSerialError;
      for (std::size_t k = 0; k < got; ++k) {
        const ReplyParser::Event e = parser_.push(rx[k]);
        if (e == ReplyParser::Event::kBadCrc) result = Status::kBadCrc;
        if (e == ReplyParser::Event::kReply) {
          if (reply_n) std::memcpy(reply, parser_.data(), reply_n);
          return Status::kOk;
        }
      }
    }
  }
  return result;
}

Status GripperBoard::get_version(Version* v) {
  std::uint8_t r[4];
  const Status s = transact(0x81, nullptr, 0, r, 4, retries_);
  if (s == Status::kOk) *v = {r[0], r[1], r[2], r[3]};
  return s;
}

Status GripperBoard::exit_safe_start() {
  return transact(0x82, nullptr, 0, nullptr, 0, retries_);
}

Status GripperBoard::open(double speed_fraction) {
  const std::uint8_t d[1] = {speed_byte(speed_fraction)};
  return transact(0x83, d, 1, nullptr, 0, retries_);
}

Status GripperBoard::close(double speed_fraction, int current_limit_ma) {
  if (current_limit_ma <= 0 || current_limit_ma > 0x3FFF) return Status::kInvalidArgument;
  const std::uint8_t d[3] = {speed_byte(speed_fraction),
                             static_cast<std::uint8_t>(current_limit_ma & 0x7F),
                             static_cast<std::uint8_t>((current_limit_ma >> 7) & 0x7F)};
  return transact(0x84, d, 3, nullptr, 0, retries_);
}

Status GripperBoard::stop() {
  return transact(0x85, nullptr, 0, nullptr, 0, retries_);
}

Status GripperBoard::go_to(int position_counts, double speed_fraction) {
  if (position_counts < 0 || position_counts > 0x3FFF) return Status::kInvalidArgument;
  const std::uint8_t d[3] = {static_cast<std::uint8_t>(position_counts & 0x7F),
                             static_cast<std::uint8_t>((position_counts >> 7) & 0x7F),
                             speed_byte(speed_fraction)};
  return transact(0x86, d, 3, nullptr, 0, retries_);
}

Status GripperBoard::calibrate() {
  return transact(0x87, nullptr, 0, nullptr, 0, retries_);
}

Status GripperBoard::get_state(State* state) {
  std::uint8_t r[8];
  const Status s = transact(0x88, nullptr, 0, r, 8, retries_);
  if (s != Status::kOk) return s;
  state->position_counts = from14(r, true);
  state->velocity_counts_s = from14(r + 2, true);
  state->current_ma = from14(r + 4, false);
  state->flags = r[6];
  state->error = r[7];
  return s;
}

Status GripperBoard::get_error(std::uint8_t* error) {
  std::uint8_t r[1];
  const Status s = transact(0x89, nullptr, 0, r, 1, 0);
  if (s == Status::kOk) *error = r[0];
  return s;
}

Status GripperBoard::set_timeout_ms(int timeout_ms) {
  if (timeout_ms < 0 || timeout_ms > 0x3FFF) return Status::kInvalidArgument;
  const std::uint8_t d[2] = {static_cast<std::uint8_t>(timeout_ms & 0x7F),
                             static_cast<std::uint8_t>((timeout_ms >> 7) & 0x7F)};
  return transact(0x8A, d, 2, nullptr, 0, retries_);
}

}  // namespace gripper
