#include "fsw_app/depth_frame_msg.hpp"

namespace fsw_app {

namespace {

// depth_frame_t on the wire: 8-byte fingerprint, utime, frame_id,
// capture_utime (8 each), width, height, num_points (4 each), then the
// planes: four floats, an int16 and a byte per point.
constexpr std::size_t kHeaderBytes = 8 + 3 * 8 + 3 * 4;
constexpr std::size_t kBytesPerPoint = 4 * 4 + 2 + 1;

std::int64_t read_be64(const std::uint8_t* p) {
  std::uint64_t v = 0;
  for (int k = 0; k < 8; ++k) v = (v << 8) | p[k];
  return static_cast<std::int64_t>(v);
}

std::int32_t read_be32(const std::uint8_t* p) {
  const std::uint32_t v = (static_cast<std::uint32_t>(p[0]) << 24) |
                          (static_cast<std::uint32_t>(p[1]) << 16) |
                          (static_cast<std::uint32_t>(p[2]) << 8) | p[3];
  return static_cast<std::int32_t>(v);
}

}  // namespace

const char* to_string(FrameMsgStatus status) {
  switch (status) {
    case FrameMsgStatus::kOk:
      return "OK";
    case FrameMsgStatus::kTruncated:
      return "TRUNCATED";
    case FrameMsgStatus::kWrongType:
      return "WRONG_TYPE";
    case FrameMsgStatus::kBadSize:
      return "BAD_SIZE";
    case FrameMsgStatus::kTooLarge:
      return "TOO_LARGE";
    case FrameMsgStatus::kTrailingBytes:
      return "TRAILING_BYTES";
    case FrameMsgStatus::kDecodeFailed:
      return "DECODE_FAILED";
  }
  return "UNKNOWN";
}

std::size_t depth_frame_encoded_size(std::size_t n_points) {
  return kHeaderBytes + kBytesPerPoint * n_points;
}

void reserve_points(hrp::depth_frame_t* msg, std::size_t max_points) {
  msg->x_m.reserve(max_points);
  msg->y_m.reserve(max_points);
  msg->z_m.reserve(max_points);
  msg->noise_m.reserve(max_points);
  msg->gray_value.reserve(max_points);
  msg->confidence.reserve(max_points);
}

void to_msg(const hal::DepthFrame& frame, hrp::depth_frame_t* msg) {
  const std::size_t n = static_cast<std::size_t>(frame.width) * frame.height;
  msg->frame_id = static_cast<std::int64_t>(frame.frame_id);
  msg->capture_utime = frame.capture_time_us;
  msg->width = static_cast<std::int32_t>(frame.width);
  msg->height = static_cast<std::int32_t>(frame.height);
  msg->num_points = static_cast<std::int32_t>(n);
  msg->x_m.resize(n);
  msg->y_m.resize(n);
  msg->z_m.resize(n);
  msg->noise_m.resize(n);
  msg->gray_value.resize(n);
  msg->confidence.resize(n);
  for (std::size_t k = 0; k < n; ++k) {
    const hal::DepthPoint& p = frame.points[k];
    msg->x_m[k] = p.x_m;
    msg->y_m[k] = p.y_m;
    msg->z_m[k] = p.z_m;
    msg->noise_m[k] = p.noise_m;
    msg->gray_value[k] = static_cast<std::int16_t>(p.gray_value);
    msg->confidence[k] = p.confidence;
  }
}

FrameMsgStatus decode_depth_frame(const void* data, std::size_t size, std::size_t max_points,
                                  hrp::depth_frame_t* msg) {
  const auto* bytes = static_cast<const std::uint8_t*>(data);
  if (data == nullptr || size < kHeaderBytes) return FrameMsgStatus::kTruncated;
  if (read_be64(bytes) != hrp::depth_frame_t::getHash()) return FrameMsgStatus::kWrongType;
  const std::int32_t width = read_be32(bytes + 32);
  const std::int32_t height = read_be32(bytes + 36);
  const std::int32_t num_points = read_be32(bytes + 40);
  if (width <= 0 || height <= 0 || num_points <= 0 ||
      static_cast<std::int64_t>(width) * height != num_points) {
    return FrameMsgStatus::kBadSize;
  }
  const auto n = static_cast<std::size_t>(num_points);
  if (n > max_points) return FrameMsgStatus::kTooLarge;
  const std::size_t expected = depth_frame_encoded_size(n);
  if (size < expected) return FrameMsgStatus::kTruncated;
  if (size > expected) return FrameMsgStatus::kTrailingBytes;
  if (msg->decode(data, 0, static_cast<int>(size)) != static_cast<int>(size)) {
    return FrameMsgStatus::kDecodeFailed;
  }
  return FrameMsgStatus::kOk;
}

void from_msg(const hrp::depth_frame_t& msg, hal::DepthPoint* points, hal::DepthFrame* frame) {
  const auto n = static_cast<std::size_t>(msg.num_points);
  for (std::size_t k = 0; k < n; ++k) {
    points[k] = hal::DepthPoint{msg.x_m[k],
                                msg.y_m[k],
                                msg.z_m[k],
                                msg.noise_m[k],
                                static_cast<std::uint16_t>(msg.gray_value[k]),
                                msg.confidence[k]};
  }
  frame->frame_id = static_cast<std::uint64_t>(msg.frame_id);
  frame->capture_time_us = msg.capture_utime;
  frame->width = static_cast<std::uint32_t>(msg.width);
  frame->height = static_cast<std::uint32_t>(msg.height);
  frame->points = points;
}

}  // namespace fsw_app
