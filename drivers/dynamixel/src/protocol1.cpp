#include "dynamixel/protocol1.hpp"

namespace dynamixel {

const char* error_bit_name(std::uint8_t bit) {
  switch (bit) {
    case 0:
      return "NONE";
    case kErrorInputVoltage:
      return "INPUT_VOLTAGE";
    case kErrorAngleLimit:
      return "ANGLE_LIMIT";
    case kErrorOverheating:
      return "OVERHEATING";
    case kErrorRange:
      return "RANGE";
    case kErrorChecksum:
      return "CHECKSUM";
    case kErrorOverload:
      return "OVERLOAD";
    case kErrorInstruction:
      return "INSTRUCTION";
    default:
      return "UNKNOWN";
  }
}

const char* to_string(ParseEvent event) {
  switch (event) {
    case ParseEvent::kNone:
      return "NONE";
    case ParseEvent::kPacket:
      return "PACKET";
    case ParseEvent::kBadChecksum:
      return "BAD_CHECKSUM";
    case ParseEvent::kBadLength:
      return "BAD_LENGTH";
  }
  return "UNKNOWN";
}

std::uint8_t checksum(std::uint8_t id, std::uint8_t length, std::uint8_t instruction_or_error,
                      const std::uint8_t* params, std::size_t n_params) {
  unsigned sum = id + length + instruction_or_error;
  for (std::size_t k = 0; k < n_params; ++k) sum += params[k];
  return static_cast<std::uint8_t>(~sum & 0xFFu);
}

namespace {
// Both directions share the framing: FF FF ID LEN CODE params CHK, where
// CODE is the instruction or the error byte.
std::size_t encode_packet(std::uint8_t id, std::uint8_t code, const std::uint8_t* params,
                          std::size_t n_params, std::uint8_t* out) {
  if (n_params > kMaxParams) return 0;
  const std::uint8_t length = static_cast<std::uint8_t>(n_params + 2);
  out[0] = 0xFF;
  out[1] = 0xFF;
  out[2] = id;
  out[3] = length;
  out[4] = code;
  for (std::size_t k = 0; k < n_params; ++k) out[5 + k] = params[k];
  out[5 + n_params] = checksum(id, length, code, params, n_params);
  return n_params + 6;
}
}  // namespace

std::size_t encode_instruction(std::uint8_t id, Instruction instruction, const std::uint8_t* params,
                               std::size_t n_params, std::uint8_t* out) {
  return encode_packet(id, static_cast<std::uint8_t>(instruction), params, n_params, out);
}

std::size_t encode_status(std::uint8_t id, std::uint8_t error, const std::uint8_t* params,
                          std::size_t n_params, std::uint8_t* out) {
  return encode_packet(id, error, params, n_params, out);
}

ParseEvent StatusParser::push(std::uint8_t byte) {
  switch (state_) {
    case State::kHeader1:
      if (byte == 0xFF) state_ = State::kHeader2;
      return ParseEvent::kNone;
    case State::kHeader2:
      state_ = byte == 0xFF ? State::kId : State::kHeader1;
      return ParseEvent::kNone;
    case State::kId:
      // A third FF is still header (the bus may idle high): stay here.
      if (byte == 0xFF) return ParseEvent::kNone;
      packet_.id = byte;
      state_ = State::kLength;
      return ParseEvent::kNone;
    case State::kLength:
      if (byte < 2 || byte > kMaxParams + 2) {
        state_ = byte == 0xFF ? State::kHeader2 : State::kHeader1;
        return ParseEvent::kBadLength;
      }
      length_ = byte;
      packet_.n_params = static_cast<std::uint8_t>(byte - 2);
      state_ = State::kError;
      return ParseEvent::kNone;
    case State::kError:
      packet_.error = byte;
      sum_ = static_cast<std::uint8_t>(packet_.id + length_ + byte);
      state_ = packet_.n_params ? State::kParams : State::kChecksum;
      length_ = 0;  // now counts parameters received
      return ParseEvent::kNone;
    case State::kParams:
      packet_.params[length_++] = byte;
      sum_ = static_cast<std::uint8_t>(sum_ + byte);
      if (length_ == packet_.n_params) state_ = State::kChecksum;
      return ParseEvent::kNone;
    case State::kChecksum:
      state_ = State::kHeader1;
      return static_cast<std::uint8_t>(~sum_) == byte ? ParseEvent::kPacket
                                                      : ParseEvent::kBadChecksum;
  }
  return ParseEvent::kNone;
}

}  // namespace dynamixel
