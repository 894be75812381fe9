#pragma once
// Dynamixel Protocol 1.0 as a pure codec: no I/O, no allocation.
//
//   instruction: FF FF ID LEN INST P1..PN CHK   LEN = N + 2
//   status:      FF FF ID LEN ERR  P1..PN CHK
//   CHK = ~(ID + LEN + INST/ERR + P1 + .. + PN) & 0xFF
#include <cstddef>
#include <cstdint>

namespace dynamixel {

constexpr std::uint8_t kBroadcastId = 0xFE;
constexpr std::size_t kMaxParams = 64;
constexpr std::size_t kMaxPacket = kMaxParams + 6;

enum class Instruction : std::uint8_t {
  kPing = 0x01,
  kRead = 0x02,
  kWrite = 0x03,
  kRegWrite = 0x04,
  kAction = 0x05,
  kReset = 0x06,
  kSyncWrite = 0x83,
};

// Servo error bits in a status packet.
enum ErrorBit : std::uint8_t {
  kErrorInputVoltage = 1u << 0,
  kErrorAngleLimit = 1u << 1,
  kErrorOverheating = 1u << 2,
  kErrorRange = 1u << 3,
  kErrorChecksum = 1u << 4,
  kErrorOverload = 1u << 5,
  kErrorInstruction = 1u << 6,
};
// The name of one error bit ("OVERLOAD", ...); "NONE" for 0.
const char* error_bit_name(std::uint8_t bit);

std::uint8_t checksum(std::uint8_t id, std::uint8_t length, std::uint8_t instruction_or_error,
                      const std::uint8_t* params, std::size_t n_params);

// Writes an instruction packet into out (capacity kMaxPacket); returns its
// size, or 0 when there are too many parameters.
std::size_t encode_instruction(std::uint8_t id, Instruction instruction, const std::uint8_t* params,
                               std::size_t n_params, std::uint8_t* out);

struct StatusPacket {
  std::uint8_t id = 0;
  std::uint8_t error = 0;
  std::uint8_t n_params = 0;
  std::uint8_t params[kMaxParams] = {};
};

enum class ParseEvent : std::uint8_t {
  kNone,         // need more bytes
  kPacket,       // a whole, valid status packet is ready
  kBadChecksum,  // a packet arrived with a wrong checksum; dropped, though packet()
                 // still shows its ID and code (a servo answers it with kErrorChecksum)
  kBadLength,    // a length byte that cannot be; resynchronising
};
const char* to_string(ParseEvent event);

// Byte-at-a-time status parser. Resynchronises on FF FF after any error, so
// a corrupt or truncated packet costs only itself.
class StatusParser {
 public:
  ParseEvent push(std::uint8_t byte);
  const StatusPacket& packet() const { return packet_; }
  void reset() { state_ = State::kHeader1; }

 private:
  enum class State : std::uint8_t { kHeader1, kHeader2, kId, kLength, kError, kParams, kChecksum };
  State state_ = State::kHeader1;
  std::uint8_t length_ = 0;
  std::uint8_t sum_ = 0;
  StatusPacket packet_;
};

// Writes a status packet (the servo's side: simulated servos use it).
std::size_t encode_status(std::uint8_t id, std::uint8_t error, const std::uint8_t* params,
                          std::size_t n_params, std::uint8_t* out);

struct InstructionPacket {
  std::uint8_t id = 0;
  std::uint8_t instruction = 0;
  std::uint8_t n_params = 0;
  const std::uint8_t* params = nullptr;  // valid until the next push()
};

// The servo's side of the wire: instruction packets share the status
// packets' framing, so this is the same resynchronising parser.
class InstructionParser {
 public:
  ParseEvent push(std::uint8_t byte) { return parser_.push(byte); }
  InstructionPacket packet() const {
    const StatusPacket& p = parser_.packet();
    return {p.id, p.error, p.n_params, p.params};
  }
  void reset() { parser_.reset(); }

 private:
  StatusParser parser_;
};

}  // namespace dynamixel
