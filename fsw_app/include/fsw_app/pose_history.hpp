#pragma once
// The robot's recent poses (ROBOT_POSE), to place a sighting with the pose
// the robot had when its frame was captured. A frame reaches the estimator
// 15 to 150 ms after its capture and the detector takes its own time; the
// robot moves up to 1.5 cm and 1.5 deg in that time, so the newest pose is
// not the camera's pose for that frame.
//
// Every message is checked as a Mailbox checks it (input_checks.hpp,
// input_gates.hpp: the filter's own, finite, in range, not stale); each
// accepted one goes into a fixed ring of kCapacity poses (about 2 s at the
// filter's 62.5 Hz). pose_at(t) interpolates between the two poses around
// t: linearly in position, along the shortest arc in attitude. It refuses
// rather than guesses: before the oldest held, across a gap wider than
// kMaxBracket_us (the filter was silent: an IMU outage), with either pose
// marked lost, or more than kMaxAhead_us after the newest. No allocation.
#include <Eigen/Geometry>
#include <array>
#include <cstdint>
#include <mutex>

#include "fsw_app/input_checks.hpp"
#include "fsw_app/lcm_hub.hpp"
#include "hrp/robot_pose_t.hpp"

namespace fsw_app {

enum class PoseAtStatus : std::uint8_t {
  kInterpolated,  // between two held poses around the time
  kNewest,        // at most kMaxAhead_us after the newest: the newest
  kNoPose,        // none held yet
  kTooOld,        // before the oldest held
  kTooNew,        // more than kMaxAhead_us after the newest
  kGap,           // the poses around it are further apart than kMaxBracket_us
  kLost,          // a pose around it is marked lost
};
constexpr int kPoseAtStatusCount = 7;
const char* to_string(PoseAtStatus status);

class PoseHistory {
 public:
  static constexpr int kCapacity = 128;
  // Wider than 4 filter periods (16 ms each) is a silence, not jitter.
  static constexpr std::int64_t kMaxBracket_us = 100'000;
  // A frame captured after the newest pose: that pose, if it is this fresh.
  static constexpr std::int64_t kMaxAhead_us = 50'000;

  // Dispatcher side (LcmHub::subscribe).
  void deliver(const void* data, std::uint32_t size, std::int64_t now_us);
  const InputCounts& input_counts() const { return box_.input_counts(); }

  // The pose at t_us; on kInterpolated and kNewest, *T_world_body.
  PoseAtStatus pose_at(std::int64_t t_us, Eigen::Isometry3d* T_world_body) const;
  // How many poses are held.
  int size() const;

 private:
  struct Stamped {
    std::int64_t utime = 0;
    Eigen::Vector3d p_world = Eigen::Vector3d::Zero();
    Eigen::Quaterniond q_world_body = Eigen::Quaterniond::Identity();
    bool lost = false;
  };
  const Stamped& at(int k) const;  // k = 0: the oldest held

  Mailbox<hrp::robot_pose_t> box_;
  hrp::robot_pose_t incoming_{};
  std::uint64_t seen_ = 0;
  mutable std::mutex mutex_;
  std::array<Stamped, kCapacity> ring_{};
  int oldest_ = 0, count_ = 0;
};

}  // namespace fsw_app
