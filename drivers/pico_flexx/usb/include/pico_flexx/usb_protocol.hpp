#pragma once
// The project's own Pico Flexx USB protocol (the vendor's is unpublished),
// as pure encoders and parsers with no I/O: the driver and the emulated
// camera both use these, and PROTOCOL.md beside this library is the
// specification. All numbers are little-endian.
//
//   command (host -> camera, bulk OUT 0x01)
//     0  'P' 'C'   magic            4  u16 payload bytes (0..16)
//     2  u8 command                 6  u16 zero
//     3  u8 tag (echoed)            8  payload, then u32 CRC-32 of all before it
//   reply (camera -> host, bulk IN 0x81)
//     0  'P' 'R'   magic            4  u8 status        6  u16 payload bytes (0..4096)
//     2  u8 command  3  u8 tag      5  u8 zero          8  payload, then u32 CRC-32
//   raw frame (camera -> host, bulk IN 0x82): a 64-byte header (FrameHeader),
//     then the payload; a frame ends with a short (or zero-length) transfer.
#include <cstddef>
#include <cstdint>

namespace pico_flexx {

constexpr std::uint16_t kVendorId = 0x1c28;
constexpr std::uint16_t kProductId = 0xc012;
constexpr std::uint16_t kProtocolVersion = 1;
constexpr std::uint8_t kInterfaceNumber = 0;
constexpr std::uint8_t kCommandEndpoint = 0x01;  // bulk OUT
constexpr std::uint8_t kReplyEndpoint = 0x81;    // bulk IN
constexpr std::uint8_t kStreamEndpoint = 0x82;   // bulk IN
constexpr std::uint16_t kBulkPacketBytes = 512;  // high speed

constexpr std::size_t kPacketHeaderBytes = 8;
constexpr std::size_t kCrcBytes = 4;
constexpr std::size_t kMaxCommandPayloadBytes = 16;
constexpr std::size_t kMaxReplyPayloadBytes = 4096;
constexpr std::size_t kMaxCommandBytes = kPacketHeaderBytes + kMaxCommandPayloadBytes + kCrcBytes;
constexpr std::size_t kMaxReplyBytes = kPacketHeaderBytes + kMaxReplyPayloadBytes + kCrcBytes;
constexpr std::size_t kSerialBytes = 16;  // NUL-padded ASCII

enum class Command : std::uint8_t {
  kIdentify = 0x01,
  kCalibrationInfo = 0x02,
  kReadCalibration = 0x03,
  kSetUseCase = 0x04,
  kSetExposureMode = 0x05,
  kSetExposureTime = 0x06,
  kStartStream = 0x07,
  kStopStream = 0x08,
};
const char* to_string(Command command);

// The camera's verdict on a command (the reply's status byte).
enum class ReplyStatus : std::uint8_t {
  kOk = 0,
  kBadCrc = 1,
  kUnknownCommand = 2,
  kBadLength = 3,
  kOutOfRange = 4,
  kBusy = 5,       // not while streaming
  kWrongMode = 6,  // an exposure time while the exposure is automatic
};
const char* to_string(ReplyStatus status);

// Why received bytes are not a valid packet or frame header.
enum class ParseStatus : std::uint8_t {
  kOk,
  kTooShort,
  kBadMagic,
  kBadLength,  // the length field disagrees with the bytes received
  kBadCrc,
  kWrongCommand,  // a reply to another command
  kWrongTag,      // a reply to an earlier command (a late reply)
  kBadVersion,
  kBadSize,  // a frame header whose sizes do not fit its use case
  // A frame header whose exposure is 0 or longer than its use case allows:
  // a frame exposed so is not what the camera was set to take.
  kBadExposure,
  // A capture time of 2^62 us or more (146,000 years of the camera's
  // clock): no counter that started at power-up reads so, and the host's
  // signed arithmetic on it would overflow.
  kBadTime,
};
const char* to_string(ParseStatus status);

struct CommandView {
  Command command = Command::kIdentify;
  std::uint8_t tag = 0;
  const std::uint8_t* payload = nullptr;
  std::size_t payload_bytes = 0;
};

struct ReplyView {
  Command command = Command::kIdentify;
  std::uint8_t tag = 0;
  ReplyStatus status = ReplyStatus::kOk;
  const std::uint8_t* payload = nullptr;
  std::size_t payload_bytes = 0;
};

// Encoders return the packet's length, 0 when the payload is too long or
// `capacity` too small.
std::size_t encode_command(Command command, std::uint8_t tag, const std::uint8_t* payload,
                           std::size_t payload_bytes, std::uint8_t* out, std::size_t capacity);
std::size_t encode_reply(Command command, std::uint8_t tag, ReplyStatus status,
                         const std::uint8_t* payload, std::size_t payload_bytes, std::uint8_t* out,
                         std::size_t capacity);
ParseStatus parse_command(const std::uint8_t* data, std::size_t length, CommandView* out);
// Checks magic, length and CRC, then that it answers `command` with `tag`.
ParseStatus parse_reply(const std::uint8_t* data, std::size_t length, Command command,
                        std::uint8_t tag, ReplyView* out);

// The IDENTIFY reply's payload.
struct Identity {
  std::uint16_t vendor_id = 0;
  std::uint16_t product_id = 0;
  std::uint16_t protocol_version = 0;
  std::uint8_t firmware_major = 0;
  std::uint8_t firmware_minor = 0;
  char serial[kSerialBytes + 1] = {};  // NUL-terminated
};
constexpr std::size_t kIdentityBytes = 8 + kSerialBytes;
void encode_identity(const Identity& identity, std::uint8_t out[kIdentityBytes]);
bool parse_identity(const std::uint8_t* data, std::size_t length, Identity* out);

// Raw frames.
constexpr std::uint32_t kFrameMagic = 0x4d524650;  // "PFRM"
constexpr std::uint16_t kFrameHeaderVersion = 1;
constexpr std::size_t kFrameHeaderBytes = 64;
constexpr std::uint16_t kBitsPerSample = 12;
// The largest payload: MODE_9, nine 224 x 171 images of 16-bit samples.
constexpr std::size_t kMaxRawPayloadBytes() {
  return 9u * 224u * 171u * 2u;
}

struct FrameHeader {
  std::uint32_t sequence = 0;       // +1 per frame the camera reads out
  std::uint32_t payload_bytes = 0;  // raw_images * width * height * 2
  std::uint8_t use_case_index = 0;  // hal::use_cases() order
  std::uint8_t raw_images = 0;      // 9 (MODE_9) or 5 (MODE_5)
  std::uint16_t width_px = 0;
  std::uint16_t height_px = 0;
  std::uint32_t exposure_us = 0;
  std::int16_t temperature_centi_c = 0;  // the imager's, 0.01 deg C
  std::uint64_t capture_time_us = 0;     // the camera's own clock
  std::uint32_t payload_checksum = 0;    // fletcher32 of the payload
};
void encode_frame_header(const FrameHeader& header, std::uint8_t out[kFrameHeaderBytes]);
// Checks magic, version, header CRC, and that the sizes fit the use case
// (a known index, its raw image count, 224 x 171, 16-bit samples).
ParseStatus parse_frame_header(const std::uint8_t* data, std::size_t length, FrameHeader* out);

// CRC-32 (IEEE 802.3: reflected polynomial 0xEDB88320, initial and final
// value 0xFFFFFFFF; "123456789" gives 0xCBF43926).
std::uint32_t crc32(const std::uint8_t* data, std::size_t length);
// Fletcher-32 over little-endian 16-bit words (an odd last byte is a word
// of its own); far cheaper than a CRC over 0.4 to 0.7 MB a frame.
std::uint32_t fletcher32(const std::uint8_t* data, std::size_t length);

inline void put_u16(std::uint8_t* p, std::uint16_t v) {
  p[0] = static_cast<std::uint8_t>(v);
  p[1] = static_cast<std::uint8_t>(v >> 8);
}
inline void put_u32(std::uint8_t* p, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) p[i] = static_cast<std::uint8_t>(v >> (8 * i));
}
inline std::uint16_t get_u16(const std::uint8_t* p) {
  return static_cast<std::uint16_t>(p[0] | (p[1] << 8));
}
inline std::uint32_t get_u32(const std::uint8_t* p) {
  return static_cast<std::uint32_t>(p[0]) | (static_cast<std::uint32_t>(p[1]) << 8) |
         (static_cast<std::uint32_t>(p[2]) << 16) | (static_cast<std::uint32_t>(p[3]) << 24);
}

}  // namespace pico_flexx
