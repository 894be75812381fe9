#pragma once
// The estimator task: takes the newest frame from the ring (older unread
// frames are dropped and counted, never queued), runs the detector with the
// frame budget of the camera's use case, tracks the handrail in the world
// frame when the robot's pose at the frame's capture is known (interpolated
// from the recent ROBOT_POSEs, pose_history.hpp), and publishes every result on
// HANDRAIL_ESTIMATE and its counters on ESTIMATOR_HEALTH once a second.
// All buffers are sized at construction; processing a frame allocates
// nothing.
#include <Eigen/Geometry>
#include <array>
#include <atomic>
#include <cstdint>
#include <thread>
#include <vector>

#include "arm/arm_model.hpp"
#include "estimator/handrail_detector.hpp"
#include "estimator/handrail_tracker.hpp"
#include "fsw_app/camera_task.hpp"
#include "fsw_app/frame_ring.hpp"
#include "fsw_app/lcm_hub.hpp"
#include "fsw_app/pose_history.hpp"
#include "hal/clock.hpp"
#include "hrp/estimator_health_t.hpp"
#include "hrp/handrail_estimate_t.hpp"
#include "hrp/robot_pose_t.hpp"

namespace fsw_app {

struct EstimatorTaskConfig {
  estimator::DetectorConfig detector;  // budget_us: the use case's frame period
  estimator::TrackerConfig tracker;
  Eigen::Isometry3d T_body_cam = Eigen::Isometry3d::Identity();
  arm::ArmGeometry arm;  // for the grasp target
  std::uint32_t max_width = 224, max_height = 171;
};

struct EstimatorCounters {
  std::uint64_t processed = 0, deadline_misses = 0, found = 0;
  // The longest time from a frame's capture to its published result: a
  // host that stalls the estimator thread shows here.
  std::int64_t longest_latency_us = 0;
  // Frames with no pose at their capture time (none yet, too old, across a
  // gap in the filter's poses, lost): not placed in the world.
  std::uint64_t without_pose = 0;
  std::array<std::uint64_t, kPoseAtStatusCount> without_pose_by_status{};  // by PoseAtStatus
};

class EstimatorTask {
 public:
  EstimatorTask(LcmHub& hub, CameraTask& camera, FrameRing& ring, const EstimatorTaskConfig& cfg,
                const hal::Clock& clock);
  ~EstimatorTask();

  void start();  // a thread of its own
  void stop();
  // Waits up to timeout_ms for a frame, then processes and publishes the
  // newest. Returns false when none came. (The thread calls this; tests
  // may too, in lock step.)
  bool process_next(int timeout_ms);
  // Publishes ESTIMATOR_HEALTH now.
  void publish_health();

  const hrp::handrail_estimate_t& last_estimate() const { return estimate_; }
  EstimatorCounters counters() const;

 private:
  class ClockTime final : public estimator::TimeSource {
   public:
    explicit ClockTime(const hal::Clock& c) : clock_(c) {}
    std::int64_t now_us() const override { return clock_.now_us(); }

   private:
    const hal::Clock& clock_;
  };
  void fill_estimate(const estimator::HandrailDetection& d);
  void note_time(std::int32_t us);

  LcmHub& hub_;
  CameraTask& camera_;
  FrameRing& ring_;
  EstimatorTaskConfig cfg_;
  const hal::Clock& clock_;
  ClockTime time_;
  estimator::HandrailDetector detector_;
  estimator::HandrailTracker tracker_;
  PoseHistory poses_;
  Publisher<hrp::handrail_estimate_t> estimate_pub_;
  Publisher<hrp::estimator_health_t> health_pub_;
  std::vector<estimator::CloudPoint> cloud_points_;
  hrp::handrail_estimate_t estimate_{};
  std::uint64_t seen_ = 0;
  // Processing times of the last kWindow frames.
  static constexpr int kWindow = 64;
  std::array<std::int32_t, kWindow> times_{};
  int n_times_ = 0, next_time_ = 0;
  std::atomic<std::uint64_t> processed_{0}, misses_{0}, found_{0}, without_pose_{0};
  std::array<std::atomic<std::uint64_t>, kPoseAtStatusCount> without_pose_by_status_{};
  std::atomic<std::int64_t> longest_latency_us_{0};
  std::int64_t last_health_us_ = 0;
  std::atomic<bool> running_{false};
  std::thread thread_;
};

}  // namespace fsw_app
