#pragma once
// Every message a task takes in is decoded aside and checked before it can
// change any state: fully consumed (no bytes left over), every number
// finite, every field in its range, and not older than the message it would
// replace. A rejected message changes nothing and is counted by channel and
// reason (InputCounts), for ESTIMATOR_HEALTH's neighbour INPUT_HEALTH, the
// run summary and its JSON.
#include <atomic>
#include <cstdint>

#include "fsw_app/wire_check.hpp"
#include "hrp/approach_status_t.hpp"
#include "hrp/arm_state_t.hpp"
#include "hrp/body_velocity_command_t.hpp"
#include "hrp/estimator_health_t.hpp"
#include "hrp/gp_pose_t.hpp"
#include "hrp/handrail_estimate_t.hpp"
#include "hrp/imu_sample_t.hpp"
#include "hrp/input_health_t.hpp"
#include "hrp/localization_health_t.hpp"
#include "hrp/perch_command_t.hpp"
#include "hrp/robot_pose_t.hpp"

namespace fsw_app {

enum class InputReject : std::uint8_t {
  kUndecodable,    // LCM's decoder refused it: wrong type, truncated
  kTrailingBytes,  // decoded, with bytes left over: not the message it claims to be
  kNotFinite,      // a NaN or infinity in a number field
  kOutOfRange,     // a field outside what the robot can be or do
  kStale,          // older than the message already held on the channel
  kBadLength,      // a string or array length field the decoder must not see (wire_check.hpp)
  kDecoderFault,   // the decoder threw: contained here, and counted (never expected)
  kFuture,         // dated ahead of the receiver's clock (input_gates.hpp)
  kSequence,       // a sample counter that does not advance, or jumps too far
  kRateLimited,    // more messages than the channel's rate bound allows
  kWrongSource,    // a ROBOT_POSE whose source is not the localization filter
};
constexpr int kInputRejectKinds = 11;
const char* to_string(InputReject reason);

// Accepted and rejected messages on one channel. Written by the dispatcher
// thread, read by anyone.
struct InputCounts {
  std::atomic<std::uint64_t> accepted{0};
  std::atomic<std::uint64_t> rejected[kInputRejectKinds]{};

  void count_rejected(InputReject reason) {
    rejected[static_cast<int>(reason)].fetch_add(1, std::memory_order_relaxed);
  }
  std::uint64_t rejected_total() const {
    std::uint64_t n = 0;
    for (const auto& r : rejected) n += r.load(std::memory_order_relaxed);
    return n;
  }
};

// Limits of what a message may say. Astrobee flies at 0.5 m/s at most; a
// module is tens of metres long; the bounds are loose around that, tight
// enough to catch garbage.
constexpr double kMaxWorldPosition_m = 1000.0;
constexpr double kMaxSpeed_mps = 5.0;
constexpr double kMaxAngularSpeed_rps = 10.0;
constexpr double kUnitQuaternionTolerance = 1e-3;
// A message more than this much older than the held one is taken as a
// restarted sender (its clock began again), not a stale copy.
constexpr std::int64_t kRestartedSenderAge_us = 10'000'000;

// The content checks, one per message type a task receives. Return true
// when acceptable; otherwise false with *why.
bool check_message(const hrp::robot_pose_t& m, InputReject* why);
bool check_message(const hrp::perch_command_t& m, InputReject* why);
bool check_message(const hrp::handrail_estimate_t& m, InputReject* why);
bool check_message(const hrp::arm_state_t& m, InputReject* why);
bool check_message(const hrp::approach_status_t& m, InputReject* why);
bool check_message(const hrp::body_velocity_command_t& m, InputReject* why);
bool check_message(const hrp::estimator_health_t& m, InputReject* why);
// IMU samples and GP poses: finite and well formed; whether a rate, a
// specific force or a covariance is plausible is the filter's judgement
// (it rejects and counts by its own status).
bool check_message(const hrp::imu_sample_t& m, InputReject* why);
bool check_message(const hrp::gp_pose_t& m, InputReject* why);
// The health reports, for their readers (tools, a ground station).
bool check_message(const hrp::input_health_t& m, InputReject* why);
bool check_message(const hrp::localization_health_t& m, InputReject* why);

// Decodes `size` bytes into *scratch and checks them. *scratch is the
// receiver's aside copy: what it holds after a rejection is not to be used.
// The length fields are walked first (wire_check.hpp), so the generated
// decoder never meets a length it would throw on or allocate for; should
// it throw anyway, the exception ends here, counted as kDecoderFault.
template <typename Msg>
bool decode_and_check(const void* data, std::uint32_t size, Msg* scratch, InputReject* why) {
  if (wire_check(static_cast<const Msg*>(nullptr), data, size) != WireFault::kNone) {
    *why = InputReject::kBadLength;
    return false;
  }
  int used = -1;
  try {
    used = scratch->decode(data, 0, static_cast<int>(size));
  } catch (...) {
    *why = InputReject::kDecoderFault;
    return false;
  }
  if (used < 0) {
    *why = InputReject::kUndecodable;
    return false;
  }
  if (static_cast<std::uint32_t>(used) != size) {
    *why = InputReject::kTrailingBytes;
    return false;
  }
  // Every type is dated on a monotonic clock that starts at boot.
  if (scratch->utime < 0) {
    *why = InputReject::kOutOfRange;
    return false;
  }
  return check_message(*scratch, why);
}

// Whether `incoming` may replace `held` (both with utime): not older, unless
// so much older that its sender must have restarted.
// Both are non-negative (decode_and_check refuses a negative utime), so
// the difference cannot overflow.
inline bool is_fresh(std::int64_t incoming_utime, std::int64_t held_utime) {
  return incoming_utime >= held_utime || held_utime - incoming_utime > kRestartedSenderAge_us;
}

}  // namespace fsw_app
