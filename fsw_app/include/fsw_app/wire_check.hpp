#pragma once
// The length fields of an encoded message, checked before LCM's generated
// C++ decoder sees them. That decoder trusts them: a string length of 0 or
// below makes std::string::assign throw std::length_error, a negative array
// count makes vector::resize throw, and a count in the millions allocates
// before the decoder finds the bytes missing. Walking the message's
// variable-length fields against its layout (the .lcm file) and what the
// receiver holds keeps every such message away from the decoder.
//
// There is one overload per message type, fixed-size ones included (their
// generated decoders read fixed fields only, each bounds-checked), so that
// a new type does not compile into a receiver until it has its own; the
// test beside this file holds each layout to the generated encoder.
#include <cstddef>
#include <cstdint>

#include "hrp/approach_status_t.hpp"
#include "hrp/arm_state_t.hpp"
#include "hrp/body_velocity_command_t.hpp"
#include "hrp/depth_frame_t.hpp"
#include "hrp/estimator_health_t.hpp"
#include "hrp/gp_pose_t.hpp"
#include "hrp/handrail_estimate_t.hpp"
#include "hrp/imu_sample_t.hpp"
#include "hrp/input_health_t.hpp"
#include "hrp/localization_health_t.hpp"
#include "hrp/perch_command_t.hpp"
#include "hrp/robot_pose_t.hpp"

namespace fsw_app {

// What the length fields may say. A string's bytes are what a receiver
// reserves for it (msg_convert.hpp), so a decoded string never grows it.
constexpr std::size_t kMaxWireStringBytes = 160;
constexpr std::int32_t kMaxWireChannels = 16;  // input_health_t: the hub's table
// depth_frame_t: the largest Pico Flexx frame (224 x 172); a receiver's own
// capacity is checked again by decode_depth_frame.
constexpr std::int32_t kMaxWireDepthPoints = 224 * 172;

enum class WireFault : std::uint8_t {
  kNone,
  kTruncated,        // a field past the end of the bytes
  kBadStringLength,  // below 1 (every LCM string carries its terminator) or above the limit
  kUnterminated,     // a string whose last byte is not its terminator, or with one before it
  kBadArrayCount,    // an array count below 0 or above what the receiver holds
};
const char* to_string(WireFault fault);

// True when the bytes' length fields are sound for Msg (the fingerprint and
// the values are the decoder's and the content checks' business).
WireFault wire_check(const hrp::arm_state_t*, const void* data, std::size_t size);
WireFault wire_check(const hrp::input_health_t*, const void* data, std::size_t size);
WireFault wire_check(const hrp::depth_frame_t*, const void* data, std::size_t size);
// Fixed-size types: nothing to walk.
inline WireFault wire_check(const hrp::approach_status_t*, const void*, std::size_t) {
  return WireFault::kNone;
}
inline WireFault wire_check(const hrp::body_velocity_command_t*, const void*, std::size_t) {
  return WireFault::kNone;
}
inline WireFault wire_check(const hrp::estimator_health_t*, const void*, std::size_t) {
  return WireFault::kNone;
}
inline WireFault wire_check(const hrp::gp_pose_t*, const void*, std::size_t) {
  return WireFault::kNone;
}
inline WireFault wire_check(const hrp::handrail_estimate_t*, const void*, std::size_t) {
  return WireFault::kNone;
}
inline WireFault wire_check(const hrp::imu_sample_t*, const void*, std::size_t) {
  return WireFault::kNone;
}
inline WireFault wire_check(const hrp::localization_health_t*, const void*, std::size_t) {
  return WireFault::kNone;
}
inline WireFault wire_check(const hrp::perch_command_t*, const void*, std::size_t) {
  return WireFault::kNone;
}
inline WireFault wire_check(const hrp::robot_pose_t*, const void*, std::size_t) {
  return WireFault::kNone;
}

}  // namespace fsw_app
