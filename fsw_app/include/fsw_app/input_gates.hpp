#pragma once
// After a message's content is checked (input_checks.hpp), it is judged
// against the receiver's own clock and the channel's own history:
//   - time: dated more than kMaxAheadOfReceiver_us ahead of the receiver's
//     clock, it is refused (kFuture). Every sender on the robot stamps with
//     the same host's CLOCK_MONOTONIC, so the tolerance only covers the
//     time between stamping and receiving. Without it, one message dated
//     30 s ahead made every real one after it "stale" or "out of order".
//   - sequence (IMU samples, GP fixes): the sender's counter must advance,
//     by at most kMaxSequenceJump; a copy of a sample, or a jump of 1e15,
//     is refused (kSequence). A sender that restarted (its counter began
//     again) is taken back once kSequenceResyncRun consecutive refused
//     samples count up by one each: copies never do.
//   - rate: more accepted messages than the channel's bound, counted over
//     a token bucket on the receiver's clock, are refused (kRateLimited).
//     The bounds are at least twice the fastest rate a sender can be
//     configured to: only a stream nobody on the robot sends trips them.
//     Refused messages take no token, so junk cannot starve the real
//     stream.
// A receiver built without a clock (a replay of a recorded run, whose
// times are the past's) judges sequence only.
#include <cstdint>

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

// The receiver's time, or kNoReceiverClock for a replay.
constexpr std::int64_t kNoReceiverClock = INT64_MIN;
constexpr std::int64_t kMaxAheadOfReceiver_us = 100'000;
constexpr std::int64_t kMaxSequenceJump = 625;  // 10 s of IMU samples at 62.5 Hz
constexpr int kSequenceResyncRun = 8;

// Messages a second a channel may carry, and how many may come at once.
struct RateBound {
  double max_per_s = 0.0;  // 0: not bounded
  double burst = 0.0;
};
// IMU 62.5 Hz; GP up to 10 Hz; the localizer's pose up to 100 Hz; the
// estimator up to 45 frames/s; the arm and manager loops up to 200 Hz
// (app_config.cpp's limits); health about 1 Hz; commands from an operator.
constexpr RateBound rate_bound(const hrp::imu_sample_t*) {
  return {250.0, 32.0};
}
constexpr RateBound rate_bound(const hrp::gp_pose_t*) {
  return {40.0, 8.0};
}
constexpr RateBound rate_bound(const hrp::robot_pose_t*) {
  return {400.0, 32.0};
}
constexpr RateBound rate_bound(const hrp::handrail_estimate_t*) {
  return {100.0, 16.0};
}
constexpr RateBound rate_bound(const hrp::arm_state_t*) {
  return {400.0, 32.0};
}
constexpr RateBound rate_bound(const hrp::approach_status_t*) {
  return {400.0, 32.0};
}
constexpr RateBound rate_bound(const hrp::body_velocity_command_t*) {
  return {400.0, 32.0};
}
constexpr RateBound rate_bound(const hrp::estimator_health_t*) {
  return {20.0, 8.0};
}
constexpr RateBound rate_bound(const hrp::perch_command_t*) {
  return {50.0, 16.0};
}
// One process each, about once a second.
constexpr RateBound rate_bound(const hrp::input_health_t*) {
  return {20.0, 8.0};
}
constexpr RateBound rate_bound(const hrp::localization_health_t*) {
  return {20.0, 8.0};
}

// The time a message is dated: its utime, and where it has one its capture
// time (never after the other on an honest sender).
template <typename Msg>
std::int64_t newest_time_us(const Msg& m) {
  return m.utime;
}
inline std::int64_t newest_time_us(const hrp::gp_pose_t& m) {
  return m.capture_utime > m.utime ? m.capture_utime : m.utime;
}
inline std::int64_t newest_time_us(const hrp::handrail_estimate_t& m) {
  return m.capture_utime > m.utime ? m.capture_utime : m.utime;
}

// Whether the type carries a sender's counter, and where.
inline bool sequence_of(const hrp::imu_sample_t& m, std::int64_t* seq) {
  *seq = m.seq;
  return true;
}
inline bool sequence_of(const hrp::gp_pose_t& m, std::int64_t* seq) {
  *seq = m.seq;
  return true;
}
template <typename Msg>
bool sequence_of(const Msg&, std::int64_t*) {
  return false;
}

inline bool dated_ahead(std::int64_t message_us, std::int64_t now_us) {
  return now_us != kNoReceiverClock && message_us > now_us + kMaxAheadOfReceiver_us;
}

// A token bucket on the receiver's clock. Dispatcher thread only.
class RateGate {
 public:
  explicit RateGate(RateBound bound) : bound_(bound), tokens_(bound.burst) {}
  // True when a message may pass now (and takes its token).
  bool admit(std::int64_t now_us) {
    if (bound_.max_per_s <= 0.0 || now_us == kNoReceiverClock) return true;
    if (last_us_ != kNoReceiverClock && now_us > last_us_) {
      tokens_ += bound_.max_per_s * 1e-6 * static_cast<double>(now_us - last_us_);
      if (tokens_ > bound_.burst) tokens_ = bound_.burst;
    }
    if (now_us > last_us_) last_us_ = now_us;
    if (tokens_ < 1.0) return false;
    tokens_ -= 1.0;
    return true;
  }

 private:
  RateBound bound_;
  double tokens_;
  std::int64_t last_us_ = kNoReceiverClock;
};

// A sender's counter must advance by 1 to kMaxSequenceJump. Dispatcher
// thread only.
class SequenceGate {
 public:
  bool admit(std::int64_t seq) {
    if (last_ < 0 || (seq > last_ && seq - last_ <= kMaxSequenceJump)) {
      last_ = seq;
      run_ = 0;
      return true;
    }
    // A restarted sender counts up from somewhere else: follow it once a
    // run of its samples counts up by one each.
    // (run_last_ < seq first: run_last_ + 1 cannot overflow then; the
    // fuzzer found INT64_MAX here.)
    run_ = (run_ > 0 && run_last_ < seq && seq - run_last_ == 1) ? run_ + 1 : 1;
    run_last_ = seq;
    if (run_ >= kSequenceResyncRun && seq >= 0) {
      last_ = seq;
      run_ = 0;
      return true;
    }
    return false;
  }

 private:
  std::int64_t last_ = -1;
  std::int64_t run_last_ = -1;
  int run_ = 0;
};

}  // namespace fsw_app
