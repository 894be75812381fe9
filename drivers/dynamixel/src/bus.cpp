#include "dynamixel/bus.hpp"

#include <cstring>

namespace dynamixel {

const char* to_string(BusStatus status) {
  switch (status) {
    case BusStatus::kOk:
      return "OK";
    case BusStatus::kTimeout:
      return "TIMEOUT";
    case BusStatus::kBadChecksum:
      return "BAD_CHECKSUM";
    case BusStatus::kWrongReply:
      return "WRONG_REPLY";
    case BusStatus::kSerialError:
      return "SERIAL_ERROR";
    case BusStatus::kInvalidArgument:
      return "INVALID_ARGUMENT";
  }
  return "UNKNOWN";
}

Bus::Bus(hal::SerialPort& port, const hal::Clock& clock, const BusConfig& config)
    : port_(port), clock_(clock), config_(config) {}

std::int64_t Bus::reply_timeout_us(std::size_t sent_bytes, std::size_t reply_bytes) const {
  const std::uint32_t baud = port_.baud() ? port_.baud() : 1000000u;
  const std::int64_t wire_us =
      static_cast<std::int64_t>((sent_bytes + reply_bytes) * 10u * 1000000u / baud) + 1;
  return wire_us + config_.return_delay_us + config_.margin_us;
}

bool Bus::replies_to(Instruction instruction, std::uint8_t id) const {
  if (id == kBroadcastId) return false;
  switch (config_.status_return_level) {
    case 0:
      return instruction == Instruction::kPing;
    case 1:
      return instruction == Instruction::kPing || instruction == Instruction::kRead;
    default:
      return true;
  }
}

BusResult Bus::wait_reply(std::uint8_t id, std::size_t expect_params, std::int64_t deadline_us,
                          StatusPacket* reply, bool* unanswered) {
  BusResult result;
  result.status = BusStatus::kTimeout;
  *unanswered = true;
  std::uint8_t rx[kMaxPacket];
  parser_.reset();
  // Bounded by the deadline; each pass takes what has arrived.
  for (int pass = 0; pass < 4 * static_cast<int>(kMaxPacket); ++pass) {
    const std::int64_t left = deadline_us - clock_.now_us();
    if (left <= 0) break;
    std::size_t n = 0;
    const hal::SerialStatus s = port_.read(rx, sizeof(rx), 1, &n, left);
    if (s == hal::SerialStatus::kTimeout) break;
    if (s != hal::SerialStatus::kOk) {
      result.status = BusStatus::kSerialError;
      result.serial_status = s;
      return result;
    }
    for (std::size_t k = 0; k < n; ++k) {
      switch (parser_.push(rx[k])) {
        case ParseEvent::kNone:
          break;
        case ParseEvent::kBadLength:
          ++counters_.bad_lengths;
          break;
        case ParseEvent::kBadChecksum:
          ++counters_.bad_checksums;
          result.status = BusStatus::kBadChecksum;
          *unanswered = false;  // most likely this attempt's reply, damaged
          break;
        case ParseEvent::kPacket: {
          const StatusPacket& p = parser_.packet();
          if (p.id == id && p.n_params == expect_params) {
            *reply = p;
            result.status = BusStatus::kOk;
            result.servo_error = p.error;
            *unanswered = false;
            return result;
          }
          ++counters_.wrong_replies;
          result.status = BusStatus::kWrongReply;
          // A servo refuses a READ it cannot carry out with its error bits
          // and no data. Kept (not taken as data), and the wait goes on: it
          // may also be a stale refusal, with the real reply still to come.
          constexpr std::uint8_t kRefusal = kErrorChecksum | kErrorInstruction | kErrorRange;
          if (p.id == id && p.n_params == 0 && (p.error & kRefusal)) {
            result.servo_error = p.error;
            *unanswered = false;
          }
          // Otherwise another servo's late reply, or a stray packet: not ours.
          break;
        }
      }
    }
  }
  if (result.status == BusStatus::kTimeout) ++counters_.timeouts;
  return result;
}

void Bus::drain_until(std::int64_t deadline_us) {
  std::uint8_t sink[kMaxPacket];
  for (int pass = 0; pass < 64; ++pass) {
    const std::int64_t left = deadline_us - clock_.now_us();
    if (left <= 0) return;
    std::size_t n = 0;
    if (port_.read(sink, sizeof(sink), sizeof(sink), &n, left) != hal::SerialStatus::kOk &&
        n == 0) {
      return;
    }
  }
}

void Bus::count_stale(const std::uint8_t* bytes, std::size_t n) {
  for (std::size_t k = 0; k < n; ++k) {
    if (stale_parser_.push(bytes[k]) == ParseEvent::kPacket) ++counters_.stale_replies;
  }
}

void Bus::discard_stale() {
  std::uint8_t rx[kMaxPacket];
  stale_parser_.reset();
  // Bounded: a pass either takes bytes or ends the loop; a device that
  // never stops talking is cut off after 64 reads.
  for (int pass = 0; pass < 64; ++pass) {
    const std::int64_t left = quiet_until_us_ - clock_.now_us();
    std::size_t n = 0;
    const hal::SerialStatus s = port_.read(rx, sizeof(rx), 1, &n, left > 0 ? left : 0);
    count_stale(rx, n);
    // Nothing more before the quiet time ends (or nothing now); a port
    // failure shows again on the write that follows.
    if (s != hal::SerialStatus::kOk) break;
  }
  // Whatever came in since the last read, and a partial packet's rest.
  port_.flush_input();
}

BusResult Bus::transact(std::uint8_t id, Instruction instruction, const std::uint8_t* params,
                        std::size_t n_params, bool expect_reply, std::size_t expect_params,
                        StatusPacket* reply) {
  BusResult result;
  const std::size_t n = encode_instruction(id, instruction, params, n_params, tx_);
  if (n == 0) {
    result.status = BusStatus::kInvalidArgument;
    return result;
  }
  ++counters_.transactions;
  const std::size_t reply_bytes = expect_reply ? expect_params + 6 : 0;
  const std::int64_t timeout_us = reply_timeout_us(n, reply_bytes);
  bool reply_outstanding = false;
  std::int64_t last_start_us = 0;
  for (unsigned attempt = 0; attempt <= config_.retries; ++attempt) {
    if (attempt > 0) ++counters_.retries;
    // Stale bytes (a late reply to an earlier instruction) must not be
    // taken for this one's.
    discard_stale();
    const std::int64_t start = clock_.now_us();
    last_start_us = start;
    const hal::SerialStatus ws = port_.write(tx_, n, reply_timeout_us(n, 0));
    if (ws != hal::SerialStatus::kOk) {
      result.status = BusStatus::kSerialError;
      result.serial_status = ws;
      // A stale byte (a late reply to an earlier packet) read back as the
      // echo: let this attempt's own reply come and go, then try again.
      // Anything else is the port's failure.
      if (ws == hal::SerialStatus::kEchoMismatch) {
        drain_until(start + timeout_us);
        continue;
      }
      break;
    }
    if (!expect_reply) break;
    StatusPacket local;
    bool unanswered = true;
    result = wait_reply(id, expect_params, start + timeout_us, &local, &unanswered);
    reply_outstanding = reply_outstanding || unanswered;
    if (result.servo_error & kErrorChecksum) {
      // The servo received a damaged instruction and did nothing: as good
      // as lost on the way, so tried again.
      ++counters_.instruction_checksum_errors;
      continue;
    }
    if (result.status == BusStatus::kOk) {
      if (reply) *reply = local;
      break;
    }
    if (result.status == BusStatus::kSerialError) break;
  }
  // An attempt went unanswered: its reply may yet come. The next
  // instruction waits until twice the reply timeout has passed since the
  // last attempt went out, and discards what arrives meanwhile.
  if (reply_outstanding) quiet_until_us_ = last_start_us + 2 * timeout_us;
  return result;
}

BusResult Bus::ping(std::uint8_t id) {
  if (id == kBroadcastId) return {BusStatus::kInvalidArgument};
  return transact(id, Instruction::kPing, nullptr, 0, true, 0, nullptr);
}

BusResult Bus::read(std::uint8_t id, std::uint8_t address, std::uint8_t length, std::uint8_t* out) {
  if (id == kBroadcastId || length == 0 || length > kMaxParams || out == nullptr) {
    return {BusStatus::kInvalidArgument};
  }
  const std::uint8_t params[2] = {address, length};
  StatusPacket reply;
  const bool answered = replies_to(Instruction::kRead, id);
  if (!answered) return {BusStatus::kInvalidArgument};  // a read nobody answers
  BusResult r = transact(id, Instruction::kRead, params, 2, true, length, &reply);
  if (r.status == BusStatus::kOk) std::memcpy(out, reply.params, length);
  return r;
}

BusResult Bus::write_at(Instruction instruction, std::uint8_t id, std::uint8_t address,
                        const std::uint8_t* data, std::uint8_t length) {
  if (length == 0 || length + 1u > kMaxParams || data == nullptr) {
    return {BusStatus::kInvalidArgument};
  }
  params_[0] = address;
  std::memcpy(params_ + 1, data, length);
  return transact(id, instruction, params_, length + 1u, replies_to(instruction, id), 0, nullptr);
}

BusResult Bus::write(std::uint8_t id, std::uint8_t address, const std::uint8_t* data,
                     std::uint8_t length) {
  return write_at(Instruction::kWrite, id, address, data, length);
}

BusResult Bus::reg_write(std::uint8_t id, std::uint8_t address, const std::uint8_t* data,
                         std::uint8_t length) {
  return write_at(Instruction::kRegWrite, id, address, data, length);
}

BusResult Bus::action(std::uint8_t id) {
  return transact(id, Instruction::kAction, nullptr, 0, replies_to(Instruction::kAction, id), 0,
                  nullptr);
}

BusResult Bus::sync_write(std::uint8_t address, std::uint8_t length, const std::uint8_t* ids,
                          const std::uint8_t* data, std::size_t n) {
  const std::size_t n_params = 2 + n * (length + 1u);
  if (length == 0 || n == 0 || n_params > kMaxParams || ids == nullptr || data == nullptr) {
    return {BusStatus::kInvalidArgument};
  }
  params_[0] = address;
  params_[1] = length;
  for (std::size_t k = 0; k < n; ++k) {
    params_[2 + k * (length + 1u)] = ids[k];
    std::memcpy(params_ + 3 + k * (length + 1u), data + k * length, length);
  }
  return transact(kBroadcastId, Instruction::kSyncWrite, params_, n_params, false, 0, nullptr);
}

BusResult Bus::read_u8(std::uint8_t id, std::uint8_t address, std::uint8_t* value) {
  return read(id, address, 1, value);
}

BusResult Bus::read_u16(std::uint8_t id, std::uint8_t address, std::uint16_t* value) {
  std::uint8_t b[2] = {0, 0};
  const BusResult r = read(id, address, 2, b);
  if (r.status == BusStatus::kOk) *value = static_cast<std::uint16_t>(b[0] | (b[1] << 8));
  return r;
}

BusResult Bus::write_u8(std::uint8_t id, std::uint8_t address, std::uint8_t value) {
  return write(id, address, &value, 1);
}

BusResult Bus::write_u16(std::uint8_t id, std::uint8_t address, std::uint16_t value) {
  const std::uint8_t b[2] = {static_cast<std::uint8_t>(value & 0xFF),
                             static_cast<std::uint8_t>(value >> 8)};
  return write(id, address, b, 2);
}

}  // namespace dynamixel
