#include "pico_flexx/usb_protocol.hpp"

#include <cstring>

#include "hal/use_case.hpp"
#include "tof/raw_frame.hpp"

namespace pico_flexx {
namespace {

constexpr std::uint8_t kCommandMagic[2] = {'P', 'C'};
constexpr std::uint8_t kReplyMagic[2] = {'P', 'R'};

// The CRC table, built at compile time.
struct CrcTable {
  std::uint32_t entry[256];
  constexpr CrcTable() : entry() {
    for (std::uint32_t i = 0; i < 256; ++i) {
      std::uint32_t c = i;
      for (int k = 0; k < 8; ++k) c = (c & 1u) ? 0xEDB88320u ^ (c >> 1) : c >> 1;
      entry[i] = c;
    }
  }
};
constexpr CrcTable kCrcTable;

std::size_t encode_packet(bool is_command, std::uint8_t command, std::uint8_t tag,
                          std::uint8_t status, const std::uint8_t* payload,
                          std::size_t payload_bytes, std::size_t max_payload, std::uint8_t* out,
                          std::size_t capacity) {
  const std::size_t total = kPacketHeaderBytes + payload_bytes + kCrcBytes;
  if (payload_bytes > max_payload || capacity < total) return 0;
  const std::uint8_t* magic = is_command ? kCommandMagic : kReplyMagic;
  out[0] = magic[0];
  out[1] = magic[1];
  out[2] = command;
  out[3] = tag;
  // Commands carry their payload length at 4; replies their status at 4 and
  // the length at 6 (see the header's layout).
  if (is_command) {
    put_u16(out + 4, static_cast<std::uint16_t>(payload_bytes));
    put_u16(out + 6, 0);
  } else {
    out[4] = status;
    out[5] = 0;
    put_u16(out + 6, static_cast<std::uint16_t>(payload_bytes));
  }
  if (payload_bytes > 0) std::memcpy(out + kPacketHeaderBytes, payload, payload_bytes);
  put_u32(out + kPacketHeaderBytes + payload_bytes, crc32(out, kPacketHeaderBytes + payload_bytes));
  return total;
}

ParseStatus check_packet(const std::uint8_t* data, std::size_t length, const std::uint8_t magic[2],
                         std::size_t payload_bytes, std::size_t max_payload) {
  if (length < kPacketHeaderBytes + kCrcBytes) return ParseStatus::kTooShort;
  if (data[0] != magic[0] || data[1] != magic[1]) return ParseStatus::kBadMagic;
  if (payload_bytes > max_payload || length != kPacketHeaderBytes + payload_bytes + kCrcBytes) {
    return ParseStatus::kBadLength;
  }
  const std::size_t body = kPacketHeaderBytes + payload_bytes;
  if (get_u32(data + body) != crc32(data, body)) return ParseStatus::kBadCrc;
  return ParseStatus::kOk;
}

}  // namespace

const char* to_string(Command command) {
  switch (command) {
    case Command::kIdentify:
      return "IDENTIFY";
    case Command::kCalibrationInfo:
      return "CALIBRATION_INFO";
    case Command::kReadCalibration:
      return "READ_CALIBRATION";
    case Command::kSetUseCase:
      return "SET_USE_CASE";
    case Command::kSetExposureMode:
      return "SET_EXPOSURE_MODE";
    case Command::kSetExposureTime:
      return "SET_EXPOSURE_TIME";
    case Command::kStartStream:
      return "START_STREAM";
    case Command::kStopStream:
      return "STOP_STREAM";
  }
  return "UNKNOWN_COMMAND";
}

const char* to_string(ReplyStatus status) {
  switch (status) {
    case ReplyStatus::kOk:
      return "OK";
    case ReplyStatus::kBadCrc:
      return "BAD_CRC";
    case ReplyStatus::kUnknownCommand:
      return "UNKNOWN_COMMAND";
    case ReplyStatus::kBadLength:
      return "BAD_LENGTH";
    case ReplyStatus::kOutOfRange:
      return "OUT_OF_RANGE";
    case ReplyStatus::kBusy:
      return "BUSY";
    case ReplyStatus::kWrongMode:
      return "WRONG_MODE";
  }
  return "UNKNOWN_REPLY_STATUS";
}

const char* to_string(ParseStatus status) {
  switch (status) {
    case ParseStatus::kOk:
      return "OK";
    case ParseStatus::kTooShort:
      return "TOO_SHORT";
    case ParseStatus::kBadMagic:
      return "BAD_MAGIC";
    case ParseStatus::kBadLength:
      return "BAD_LENGTH";
    case ParseStatus::kBadCrc:
      return "BAD_CRC";
    case ParseStatus::kWrongCommand:
      return "WRONG_COMMAND";
    case ParseStatus::kWrongTag:
      return "WRONG_TAG";
    case ParseStatus::kBadVersion:
      return "BAD_VERSION";
    case ParseStatus::kBadSize:
      return "BAD_SIZE";
    case ParseStatus::kBadExposure:
      return "BAD_EXPOSURE";
    case ParseStatus::kBadTime:
      return "BAD_TIME";
  }
  return "UNKNOWN_PARSE_STATUS";
}

std::size_t encode_command(Command command, std::uint8_t tag, const std::uint8_t* payload,
                           std::size_t payload_bytes, std::uint8_t* out, std::size_t capacity) {
  return encode_packet(true, static_cast<std::uint8_t>(command), tag, 0, payload, payload_bytes,
                       kMaxCommandPayloadBytes, out, capacity);
}

std::size_t encode_reply(Command command, std::uint8_t tag, ReplyStatus status,
                         const std::uint8_t* payload, std::size_t payload_bytes, std::uint8_t* out,
                         std::size_t capacity) {
  return encode_packet(false, static_cast<std::uint8_t>(command), tag,
                       static_cast<std::uint8_t>(status), payload, payload_bytes,
                       kMaxReplyPayloadBytes, out, capacity);
}

ParseStatus parse_command(const std::uint8_t* data, std::size_t length, CommandView* out) {
  if (length < kPacketHeaderBytes) return ParseStatus::kTooShort;
  const std::size_t payload_bytes = get_u16(data + 4);
  const ParseStatus s =
      check_packet(data, length, kCommandMagic, payload_bytes, kMaxCommandPayloadBytes);
  if (s != ParseStatus::kOk) return s;
  out->command = static_cast<Command>(data[2]);
  out->tag = data[3];
  out->payload = data + kPacketHeaderBytes;
  out->payload_bytes = payload_bytes;
  return ParseStatus::kOk;
}

ParseStatus parse_reply(const std::uint8_t* data, std::size_t length, Command command,
                        std::uint8_t tag, ReplyView* out) {
  if (length < kPacketHeaderBytes) return ParseStatus::kTooShort;
  const std::size_t payload_bytes = get_u16(data + 6);
  const ParseStatus s =
      check_packet(data, length, kReplyMagic, payload_bytes, kMaxReplyPayloadBytes);
  if (s != ParseStatus::kOk) return s;
  if (data[2] != static_cast<std::uint8_t>(command)) return ParseStatus::kWrongCommand;
  if (data[3] != tag) return ParseStatus::kWrongTag;
  out->command = command;
  out->tag = tag;
  out->status = static_cast<ReplyStatus>(data[4]);
  out->payload = data + kPacketHeaderBytes;
  out->payload_bytes = payload_bytes;
  return ParseStatus::kOk;
}

void encode_identity(const Identity& identity, std::uint8_t out[kIdentityBytes]) {
  put_u16(out, identity.vendor_id);
  put_u16(out + 2, identity.product_id);
  put_u16(out + 4, identity.protocol_version);
  out[6] = identity.firmware_major;
  out[7] = identity.firmware_minor;
  std::memset(out + 8, 0, kSerialBytes);
  std::memcpy(out + 8, identity.serial, strnlen(identity.serial, kSerialBytes));
}

bool parse_identity(const std::uint8_t* data, std::size_t length, Identity* out) {
  if (length != kIdentityBytes) return false;
  out->vendor_id = get_u16(data);
  out->product_id = get_u16(data + 2);
  out->protocol_version = get_u16(data + 4);
  out->firmware_major = data[6];
  out->firmware_minor = data[7];
  std::memcpy(out->serial, data + 8, kSerialBytes);
  out->serial[kSerialBytes] = '\0';
  return true;
}

void encode_frame_header(const FrameHeader& h, std::uint8_t out[kFrameHeaderBytes]) {
  std::memset(out, 0, kFrameHeaderBytes);
  put_u32(out, kFrameMagic);
  put_u16(out + 4, kFrameHeaderVersion);
  put_u16(out + 6, static_cast<std::uint16_t>(kFrameHeaderBytes));
  put_u32(out + 8, h.sequence);
  put_u32(out + 12, h.payload_bytes);
  out[16] = h.use_case_index;
  out[17] = h.raw_images;
  put_u16(out + 18, h.width_px);
  put_u16(out + 20, h.height_px);
  put_u16(out + 22, kBitsPerSample);
  put_u32(out + 24, h.exposure_us);
  put_u16(out + 28, static_cast<std::uint16_t>(h.temperature_centi_c));
  put_u32(out + 32, static_cast<std::uint32_t>(h.capture_time_us));
  put_u32(out + 36, static_cast<std::uint32_t>(h.capture_time_us >> 32));
  put_u32(out + 40, h.payload_checksum);
  put_u32(out + 60, crc32(out, 60));
}

ParseStatus parse_frame_header(const std::uint8_t* data, std::size_t length, FrameHeader* out) {
  if (length < kFrameHeaderBytes) return ParseStatus::kTooShort;
  if (get_u32(data) != kFrameMagic) return ParseStatus::kBadMagic;
  if (get_u32(data + 60) != crc32(data, 60)) return ParseStatus::kBadCrc;
  if (get_u16(data + 4) != kFrameHeaderVersion || get_u16(data + 6) != kFrameHeaderBytes ||
      get_u16(data + 22) != kBitsPerSample) {
    return ParseStatus::kBadVersion;
  }
  FrameHeader h;
  h.sequence = get_u32(data + 8);
  h.payload_bytes = get_u32(data + 12);
  h.use_case_index = data[16];
  h.raw_images = data[17];
  h.width_px = get_u16(data + 18);
  h.height_px = get_u16(data + 20);
  h.exposure_us = get_u32(data + 24);
  h.temperature_centi_c = static_cast<std::int16_t>(get_u16(data + 28));
  h.capture_time_us = get_u32(data + 32) | (static_cast<std::uint64_t>(get_u32(data + 36)) << 32);
  h.payload_checksum = get_u32(data + 40);
  std::size_t use_case_count = 0;
  const hal::UseCase* use_cases = hal::use_cases(&use_case_count);
  if (h.use_case_index >= use_case_count ||
      h.raw_images != use_cases[h.use_case_index].raw_frames || h.width_px != tof::kWidthPx ||
      h.height_px != tof::kHeightPx ||
      h.payload_bytes != static_cast<std::uint32_t>(h.raw_images) * tof::kPixels * 2u) {
    return ParseStatus::kBadSize;
  }
  if (h.exposure_us == 0 || h.exposure_us > use_cases[h.use_case_index].max_exposure_us) {
    return ParseStatus::kBadExposure;
  }
  if (h.capture_time_us >= (std::uint64_t{1} << 62)) return ParseStatus::kBadTime;
  *out = h;
  return ParseStatus::kOk;
}

std::uint32_t crc32(const std::uint8_t* data, std::size_t length) {
  std::uint32_t c = 0xFFFFFFFFu;
  for (std::size_t i = 0; i < length; ++i) c = kCrcTable.entry[(c ^ data[i]) & 0xFFu] ^ (c >> 8);
  return c ^ 0xFFFFFFFFu;
}

std::uint32_t fletcher32(const std::uint8_t* data, std::size_t length) {
  // Sums of 16-bit words modulo 65535, reduced every 359 words: the most
  // that keeps both 32-bit sums from overflowing.
  std::uint32_t a = 0xFFFF, b = 0xFFFF;
  std::size_t words = length / 2;
  const std::uint8_t* p = data;
  while (words > 0) {
    const std::size_t block = words < 359 ? words : 359;
    words -= block;
    for (std::size_t i = 0; i < block; ++i, p += 2) {
      a += static_cast<std::uint32_t>(p[0] | (p[1] << 8));
      b += a;
    }
    a = (a & 0xFFFF) + (a >> 16);
    b = (b & 0xFFFF) + (b >> 16);
  }
  if (length % 2 != 0) {
    a += *p;
    b += a;
    a = (a & 0xFFFF) + (a >> 16);
    b = (b & 0xFFFF) + (b >> 16);
  }
  a = (a & 0xFFFF) + (a >> 16);
  b = (b & 0xFFFF) + (b >> 16);
  return (b << 16) | a;
}

}  // namespace pico_flexx
