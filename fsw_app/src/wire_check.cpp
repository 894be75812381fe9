#include "fsw_app/wire_check.hpp"

#include <cstring>

namespace fsw_app {

const char* to_string(WireFault fault) {
  switch (fault) {
    case WireFault::kNone:
      return "NONE";
    case WireFault::kTruncated:
      return "TRUNCATED";
    case WireFault::kBadStringLength:
      return "BAD_STRING_LENGTH";
    case WireFault::kUnterminated:
      return "UNTERMINATED";
    case WireFault::kBadArrayCount:
      return "BAD_ARRAY_COUNT";
  }
  return "UNKNOWN";
}

namespace {

// A cursor over the encoded bytes (big-endian, as LCM writes them). The
// first fault sticks; every later step is a no-op.
class WireReader {
 public:
  WireReader(const void* data, std::size_t size)
      : bytes_(static_cast<const std::uint8_t*>(data)), size_(size) {}
  WireFault fault() const { return fault_; }

  // The 8-byte fingerprint and `n` bytes of fixed fields.
  void skip(std::size_t n) {
    if (fault_ != WireFault::kNone) return;
    if (n > size_ - pos_) {
      fail(WireFault::kTruncated);
      return;
    }
    pos_ += n;
  }
  std::int32_t int32() {
    if (fault_ != WireFault::kNone) return 0;
    if (size_ - pos_ < 4) {
      fail(WireFault::kTruncated);
      return 0;
    }
    const std::uint8_t* p = bytes_ + pos_;
    pos_ += 4;
    const std::uint32_t v = (std::uint32_t{p[0]} << 24) | (std::uint32_t{p[1]} << 16) |
                            (std::uint32_t{p[2]} << 8) | std::uint32_t{p[3]};
    return static_cast<std::int32_t>(v);
  }
  // An LCM string: int32 length (terminator included), the bytes, a NUL.
  void string() {
    const std::int32_t len = int32();
    if (fault_ != WireFault::kNone) return;
    if (len < 1 || static_cast<std::size_t>(len) > kMaxWireStringBytes + 1) {
      fail(WireFault::kBadStringLength);
      return;
    }
    const std::size_t n = static_cast<std::size_t>(len);
    if (n > size_ - pos_) {
      fail(WireFault::kTruncated);
      return;
    }
    // Exactly one terminator, at the end: a NUL inside would make the held
    // string differ from what it says it is (its size counts past it).
    if (bytes_[pos_ + n - 1] != 0 || std::memchr(bytes_ + pos_, 0, n - 1) != nullptr) {
      fail(WireFault::kUnterminated);
      return;
    }
    pos_ += n;
  }
  // An array count read earlier, within [0, max].
  bool count_within(std::int32_t count, std::int32_t max) {
    if (fault_ != WireFault::kNone) return false;
    if (count < 0 || count > max) {
      fail(WireFault::kBadArrayCount);
      return false;
    }
    return true;
  }
  // `count` elements of `bytes_each`.
  void array(std::int32_t count, std::size_t bytes_each) {
    skip(static_cast<std::size_t>(count) * bytes_each);
  }

 private:
  void fail(WireFault f) {
    if (fault_ == WireFault::kNone) fault_ = f;
  }
  const std::uint8_t* bytes_;
  std::size_t size_;
  std::size_t pos_ = 0;
  WireFault fault_ = WireFault::kNone;
};

constexpr std::size_t kFingerprint = 8;

}  // namespace

// arm_state_t.lcm: utime, state, state_name, state_entered_utime,
// fault_code, fault_name, fault_state, fault_text, last_command_sequence,
// last_command, last_reject, last_reject_name, then fixed fields only.
WireFault wire_check(const hrp::arm_state_t*, const void* data, std::size_t size) {
  WireReader r(data, size);
  r.skip(kFingerprint + 8 + 1);
  r.string();
  r.skip(8 + 1);
  r.string();
  r.skip(1);
  r.string();
  r.skip(4 + 1 + 1);
  r.string();
  return r.fault();
}

// input_health_t.lcm: utime, tasks, num_channels, channel[num_channels],
// num_reasons, reason[num_reasons], accepted[num_channels],
// rejected[num_channels][num_reasons].
WireFault wire_check(const hrp::input_health_t*, const void* data, std::size_t size) {
  WireReader r(data, size);
  r.skip(kFingerprint + 8);
  r.string();
  const std::int32_t channels = r.int32();
  if (!r.count_within(channels, kMaxWireChannels)) return r.fault();
  for (std::int32_t k = 0; k < channels; ++k) r.string();
  const std::int32_t reasons = r.int32();
  if (!r.count_within(reasons, hrp::input_health_t::MAX_REASONS)) return r.fault();
  for (std::int32_t k = 0; k < reasons; ++k) r.string();
  r.array(channels, 8);
  r.array(channels * reasons, 8);
  return r.fault();
}

// depth_frame_t.lcm: utime, frame_id, capture_utime, width, height,
// num_points, then six arrays of num_points.
WireFault wire_check(const hrp::depth_frame_t*, const void* data, std::size_t size) {
  WireReader r(data, size);
  r.skip(kFingerprint + 3 * 8 + 2 * 4);
  const std::int32_t n = r.int32();
  if (!r.count_within(n, kMaxWireDepthPoints)) return r.fault();
  r.array(n, 4 * 4 + 2 + 1);
  return r.fault();
}

}  // namespace fsw_app
