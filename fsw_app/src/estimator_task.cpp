#include "fsw_app/estimator_task.hpp"

#include <algorithm>

#include "fsw_app/msg_convert.hpp"

namespace fsw_app {

EstimatorTask::EstimatorTask(LcmHub& hub, CameraTask& camera, FrameRing& ring,
                             const EstimatorTaskConfig& cfg, const hal::Clock& clock)
    : hub_(hub),
      camera_(camera),
      ring_(ring),
      cfg_(cfg),
      clock_(clock),
      time_(clock),
      detector_(cfg.detector, &time_),
      tracker_(cfg.tracker),
      estimate_pub_(hub, channel::kHandrailEstimate),
      health_pub_(hub, channel::kEstimatorHealth),
      cloud_points_(static_cast<std::size_t>(cfg.max_width) * cfg.max_height) {
  hub_.subscribe(channel::kRobotPose, &poses_);
  last_health_us_ = clock_.now_us();
}

EstimatorTask::~EstimatorTask() {
  stop();
}

void EstimatorTask::start() {
  if (running_.exchange(true)) return;
  thread_ = std::thread([this] {
    while (running_.load()) {
      process_next(100);
      if (clock_.now_us() - last_health_us_ >= 1000000) publish_health();
    }
  });
}

void EstimatorTask::stop() {
  if (!running_.exchange(false)) return;
  if (thread_.joinable()) thread_.join();
}

EstimatorCounters EstimatorTask::counters() const {
  EstimatorCounters c{processed_.load(),          misses_.load(),       found_.load(),
                      longest_latency_us_.load(), without_pose_.load(), {}};
  for (int k = 0; k < kPoseAtStatusCount; ++k) {
    c.without_pose_by_status[static_cast<std::size_t>(k)] =
        without_pose_by_status_[static_cast<std::size_t>(k)].load();
  }
  return c;
}

void EstimatorTask::note_time(std::int32_t us) {
  times_[static_cast<std::size_t>(next_time_)] = us;
  next_time_ = (next_time_ + 1) % kWindow;
  n_times_ = std::min(n_times_ + 1, kWindow);
}

bool EstimatorTask::process_next(int timeout_ms) {
  seen_ = camera_.wait_for_frame(seen_, timeout_ms);
  hal::DepthFrame frame;
  const auto to_cloud_point = [](const hal::DepthPoint& p) {
    return estimator::CloudPoint{p.x_m, p.y_m, p.z_m, p.noise_m, p.gray_value, p.confidence};
  };
  if (ring_.pop_newest_as(&frame, cloud_points_.data(), to_cloud_point) != RingStatus::kOk) {
    return false;
  }
  estimator::OrganizedCloud cloud;
  cloud.frame_id = frame.frame_id;
  cloud.capture_time_us = frame.capture_time_us;
  cloud.width = frame.width;
  cloud.height = frame.height;
  cloud.points = cloud_points_.data();
  const estimator::HandrailDetection d = detector_.detect(cloud);
  fill_estimate(d);
  estimate_pub_.publish(estimate_);
  const std::int64_t latency_us = estimate_.utime - frame.capture_time_us;
  if (latency_us > longest_latency_us_.load()) longest_latency_us_.store(latency_us);
  processed_.fetch_add(1);
  if (d.status == estimator::DetectStatus::kDeadlineMissed) misses_.fetch_add(1);
  if (d.status == estimator::DetectStatus::kFound) found_.fetch_add(1);
  note_time(static_cast<std::int32_t>(d.processing_time_us));
  return true;
}

void EstimatorTask::fill_estimate(const estimator::HandrailDetection& d) {
  hrp::handrail_estimate_t& m = estimate_;
  m.utime = clock_.now_us();
  m.frame_id = static_cast<std::int64_t>(d.frame_id);
  m.capture_utime = d.capture_time_us;
  m.state = static_cast<std::int8_t>(d.state);
  m.detect_status = static_cast<std::int8_t>(d.status);
  m.deadline_missed = d.status == estimator::DetectStatus::kDeadlineMissed;
  m.processing_us = static_cast<std::int32_t>(d.processing_time_us);
  m.inliers = static_cast<std::int32_t>(d.inliers);
  clear(&m.T_cam_handrail);
  clear(&m.T_body_handrail);
  clear(&m.T_body_target);
  clear(&m.T_world_target);
  clear(&m.T_world_handrail);
  m.target_in_world = false;
  m.num_ends = 0;
  for (auto& e : m.ends_cam_m)
    for (double& v : e) v = 0.0;
  m.bar_length_m = 0.0;

  // The camera's pose is the robot's at the frame's capture, not at this
  // moment: placed with the newest pose, a sighting would carry the
  // robot's motion over the frame's transfer and the detector's time.
  Eigen::Isometry3d T_world_body = Eigen::Isometry3d::Identity();
  const PoseAtStatus at_capture = poses_.pose_at(d.capture_time_us, &T_world_body);
  const bool have_pose =
      at_capture == PoseAtStatus::kInterpolated || at_capture == PoseAtStatus::kNewest;
  if (!have_pose) {
    without_pose_.fetch_add(1);
    without_pose_by_status_[static_cast<std::size_t>(at_capture)].fetch_add(1);
  }
  if (have_pose) {
    // The tracker runs on every frame, found or not (a miss ages the track).
    tracker_.update(d, T_world_body.cast<float>(), cfg_.T_body_cam.cast<float>());
  }
  if (d.status != estimator::DetectStatus::kFound) return;

  Eigen::Isometry3d T_cam_handrail = Eigen::Isometry3d::Identity();
  T_cam_handrail.linear() = d.R_cam_handrail.cast<double>();
  T_cam_handrail.translation() = d.p_cam_center.cast<double>();
  const Eigen::Isometry3d T_body_handrail = cfg_.T_body_cam * T_cam_handrail;
  to_msg(T_cam_handrail, &m.T_cam_handrail);
  to_msg(T_body_handrail, &m.T_body_handrail);
  to_msg(arm::grasp_body_target(cfg_.arm, T_body_handrail, Eigen::Vector3d::UnitZ()),
         &m.T_body_target);
  for (int e = 0; e < 2; ++e) {
    if (!d.end_seen[e]) continue;
    for (int k = 0; k < 3; ++k) m.ends_cam_m[m.num_ends][k] = d.ends_cam[e][k];
    ++m.num_ends;
  }
  m.bar_length_m = d.beam_length_m;
  const estimator::TrackedHandrail& track = tracker_.track();
  if (have_pose && track.valid) {
    Eigen::Isometry3d T_world_handrail = Eigen::Isometry3d::Identity();
    T_world_handrail.linear() = track.R_world_handrail.cast<double>();
    T_world_handrail.translation() = track.p_world_center.cast<double>();
    to_msg(T_world_handrail, &m.T_world_handrail);
    to_msg(arm::grasp_body_target(cfg_.arm, T_world_handrail, T_world_body.linear().col(2)),
           &m.T_world_target);
    m.target_in_world = true;
  }
}

void EstimatorTask::publish_health() {
  hrp::estimator_health_t h{};
  h.utime = clock_.now_us();
  h.frames_received = static_cast<std::int64_t>(camera_.received());
  h.frames_processed = static_cast<std::int64_t>(processed_.load());
  h.frames_dropped = static_cast<std::int64_t>(ring_.dropped());
  h.frames_corrupt = static_cast<std::int64_t>(camera_.corrupt());
  h.deadline_misses = static_cast<std::int64_t>(misses_.load());
  h.budget_us = static_cast<std::int32_t>(cfg_.detector.budget_us);
  h.window_frames = n_times_;
  if (n_times_ > 0) {
    std::array<std::int32_t, kWindow> sorted = times_;
    std::sort(sorted.begin(), sorted.begin() + n_times_);
    h.processing_min_us = sorted[0];
    h.processing_median_us = sorted[static_cast<std::size_t>(n_times_ / 2)];
    h.processing_max_us = sorted[static_cast<std::size_t>(n_times_ - 1)];
  }
  health_pub_.publish(h);
  last_health_us_ = h.utime;
}

}  // namespace fsw_app
