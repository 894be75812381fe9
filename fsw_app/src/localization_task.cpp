#include "fsw_app/localization_task.hpp"

#include <algorithm>
#include <cmath>

#include "fsw_app/msg_convert.hpp"

namespace fsw_app {

namespace loc = estimator::localization;

static_assert(loc::kNumImuStatus == 8, "localization_health_t.imu_counts has 8 entries");
static_assert(loc::kNumUpdateStatus == 16, "localization_health_t's update counts have 16");

LocalizationTask::LocalizationTask(LcmHub& hub, const LocalizationTaskConfig& cfg,
                                   const hal::Clock& clock)
    : hub_(hub),
      cfg_(cfg),
      clock_(clock),
      filter_(std::make_unique<loc::LocalizationFilter>(cfg.filter)),
      measurement_(std::make_unique<loc::HandrailMeasurement>()),
      pose_pub_(hub, channel::kRobotPose),
      health_pub_(hub, channel::kLocalizationHealth) {
  hub_.subscribe(channel::kImuSample, &imu_queue_);
  hub_.subscribe(channel::kGpPose, &gp_queue_);
  hub_.subscribe(channel::kHandrailEstimate, &handrail_box_);
  last_health_us_ = clock_.now_us();
}

LocalizationTask::~LocalizationTask() {
  stop();
}

void LocalizationTask::start() {
  const auto period_us = static_cast<std::int64_t>(1e6 / cfg_.rate_hz);
  thread_.start(period_us, [this] {
    step();
    if (clock_.now_us() - last_health_us_ >= 1000000) publish_health();
  });
}

void LocalizationTask::stop() {
  thread_.stop();
}

LocalizationTaskCounters LocalizationTask::counters() const {
  LocalizationTaskCounters c;
  c.imu_in = imu_in_.load();
  c.gp_in = gp_in_.load();
  c.gp_held_off = gp_held_off_.load();
  c.handrail_in = handrail_in_.load();
  c.imu_seq_gaps = imu_seq_gaps_.load();
  c.imu_queue_overflows = imu_queue_.overflows();
  c.handrail_unusable = handrail_unusable_.load();
  c.handrail_accepted_be = handrail_accepted_be_.load();
  c.handrail_accepted_oe = handrail_accepted_oe_.load();
  c.handrail_accepted_ne = handrail_accepted_ne_.load();
  c.handrail_oe_as_ne = handrail_oe_as_ne_.load();
  c.poses_published = poses_published_.load();
  c.gp_fallback_accepted = gp_fallback_accepted_.load();
  c.position_sigma_m = position_sigma_m_.load();
  c.position_sigma_held_min_m = position_sigma_held_min_m_.load();
  c.across_bar_sigma_m = across_bar_sigma_m_.load();
  c.across_bar_sigma_held_min_m = across_bar_sigma_held_min_m_.load();
  return c;
}

loc::UpdateStatus LocalizationTask::set_handrail_survey(const loc::HandrailMap& survey) {
  return filter_->set_handrail_survey(survey);
}

void LocalizationTask::step() {
  // IMU samples first, in order: the measurements below are placed in time
  // against them (a late one inside the history is applied at its capture).
  while (imu_queue_.pop(&imu_)) {
    imu_in_.fetch_add(1);
    if (last_imu_seq_ >= 0 && imu_.seq > last_imu_seq_ + 1) {
      imu_seq_gaps_.fetch_add(static_cast<std::uint64_t>(imu_.seq - last_imu_seq_ - 1));
    }
    last_imu_seq_ = imu_.seq;
    loc::ImuSample s;
    s.t_us = imu_.utime;
    s.omega_body_radps = Eigen::Vector3d(imu_.omega_body_radps[0], imu_.omega_body_radps[1],
                                         imu_.omega_body_radps[2]);
    s.a_body_mps2 = Eigen::Vector3d(imu_.a_body_mps2[0], imu_.a_body_mps2[1], imu_.a_body_mps2[2]);
    const loc::ImuStatus st = filter_->add_imu(s);
    if (st == loc::ImuStatus::kPropagated || st == loc::ImuStatus::kGapBridged ||
        st == loc::ImuStatus::kGapLost || st == loc::ImuStatus::kBuffered) {
      last_omega_body_ = s.omega_body_radps;
    }
  }
  while (gp_queue_.pop(&gp_)) {
    gp_in_.fetch_add(1);
    if (!cfg_.gp_while_handrail_holds && filter_->handrail_holding()) {
      gp_held_off_.fetch_add(1);
      continue;
    }
    loc::GpPose g;
    g.capture_time_us = gp_.capture_utime;
    const Eigen::Isometry3d T = from_msg(gp_.T_world_body);
    g.p_world_body_m = T.translation();
    g.q_world_body = Eigen::Quaterniond(T.linear());
    for (int r = 0; r < 6; ++r)
      for (int c = 0; c < 6; ++c) g.cov(r, c) = gp_.covariance[r][c];
    // Counted by the filter, by status; here only the fall-back on it.
    const bool fallback = handrail_has_held_ && !filter_->handrail_holding();
    if (filter_->add_gp_pose(g) == loc::UpdateStatus::kAccepted && fallback) {
      gp_fallback_accepted_.fetch_add(1);
    }
  }
  const std::uint64_t seq = handrail_box_.read(&handrail_);
  if (seq != handrail_seen_) {
    handrail_seen_ = seq;
    take_handrail(handrail_);
  }
  if (filter_->initialized() && filter_->time_us() > published_t_us_) {
    published_t_us_ = filter_->time_us();
    fill_pose();
    pose_pub_.publish(pose_);
    poses_published_.fetch_add(1);
    note_sigmas();
  }
}

void LocalizationTask::note_sigmas() {
  Eigen::Matrix3d P = Eigen::Matrix3d::Zero();
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) P(r, c) = pose_.pose_covariance[r][c];
  const double sigma_m = std::sqrt(P.diagonal().maxCoeff());
  // Across the bar: relative to the map (the handrail frame's x, the wall
  // normal, and y), not in the world, whose covariance holds the map's own.
  double across_m = -1.0;
  const loc::PoseEstimate est = filter_->estimate();
  if (est.handrail_map_valid) {
    const Eigen::Matrix3d& Ph = est.handrail_position_cov;
    across_m = std::sqrt(std::max(Ph(0, 0), Ph(1, 1)));
  }
  position_sigma_m_.store(sigma_m);
  across_bar_sigma_m_.store(across_m);
  if (pose_.handrail_holding) {
    // The smallest while the handrail held: just after an update (the
    // newest could be up to handrail_hold_s of propagation later).
    handrail_has_held_ = true;
    const double held_m = position_sigma_held_min_m_.load();
    if (held_m < 0.0 || sigma_m < held_m) position_sigma_held_min_m_.store(sigma_m);
    const double across_held_m = across_bar_sigma_held_min_m_.load();
    if (across_m >= 0.0 && (across_held_m < 0.0 || across_m < across_held_m)) {
      across_bar_sigma_held_min_m_.store(across_m);
    }
  }
}

void LocalizationTask::take_handrail(const hrp::handrail_estimate_t& e) {
  handrail_in_.fetch_add(1);
  if (e.state == hrp::handrail_estimate_t::STATE_BE && !e.deadline_missed) {
    (void)bar_length_.add_both_ends(e.bar_length_m);
  }
  if (handrail_measurement_from(e, cfg_.handrail, bar_length_.length_m(), measurement_.get()) !=
      HandrailMeasurementStatus::kOk) {
    handrail_unusable_.fetch_add(1);
    return;
  }
  if (e.state == hrp::handrail_estimate_t::STATE_OE &&
      measurement_->state == estimator::HandrailState::kNoEnd) {
    handrail_oe_as_ne_.fetch_add(1);
  }
  // Counted by the filter by status; here by the state it was taken in.
  if (filter_->add_handrail(*measurement_) != loc::UpdateStatus::kAccepted) return;
  switch (measurement_->state) {
    case estimator::HandrailState::kBothEnds:
      handrail_accepted_be_.fetch_add(1);
      break;
    case estimator::HandrailState::kOneEnd:
      handrail_accepted_oe_.fetch_add(1);
      break;
    default:
      handrail_accepted_ne_.fetch_add(1);
      break;
  }
}

void LocalizationTask::fill_pose() {
  const loc::PoseEstimate est = filter_->estimate();
  pose_.utime = est.t_us;
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = est.q_world_body.normalized().toRotationMatrix();
  T.translation() = est.p_world_body_m;
  to_msg(T, &pose_.T_world_body);
  // The body's rate: the newest sample less the estimated gyro bias, in
  // the world frame as the message has it.
  const Eigen::Vector3d w_world = T.linear() * (last_omega_body_ - est.gyro_bias_radps);
  for (int k = 0; k < 3; ++k) {
    pose_.velocity_mps[k] = est.v_world_body_mps[k];
    pose_.angular_velocity_rps[k] = w_world[k];
  }
  pose_.source = hrp::robot_pose_t::SOURCE_FILTER;
  pose_.lost = est.lost;
  pose_.handrail_holding = est.handrail_holding;
  for (int r = 0; r < 6; ++r)
    for (int c = 0; c < 6; ++c) pose_.pose_covariance[r][c] = est.pose_cov(r, c);
}

void LocalizationTask::publish_health() {
  hrp::localization_health_t& h = health_;
  h.utime = clock_.now_us();
  const loc::PoseEstimate est = filter_->estimate();
  h.initialized = est.initialized;
  h.lost = est.lost;
  h.handrail_map_valid = est.handrail_map_valid;
  const loc::FilterCounters& c = filter_->counters();
  for (int k = 0; k < loc::kNumImuStatus; ++k)
    h.imu_counts[k] = static_cast<std::int64_t>(c.imu[k]);
  const auto kind = [&c](loc::MeasurementKind m, int s) {
    return static_cast<std::int64_t>(c.updates[static_cast<std::size_t>(m)][s]);
  };
  for (int s = 0; s < loc::kNumUpdateStatus; ++s) {
    h.gp_counts[s] = kind(loc::MeasurementKind::kGpPose, s);
    h.handrail_ends_counts[s] = kind(loc::MeasurementKind::kHandrailEnds, s);
    h.handrail_no_end_counts[s] = kind(loc::MeasurementKind::kHandrailNoEnd, s);
  }
  h.features_gated = static_cast<std::int64_t>(c.features_gated);
  h.imu_seq_gaps = static_cast<std::int64_t>(imu_seq_gaps_.load());
  h.handrail_unusable = static_cast<std::int64_t>(handrail_unusable_.load());
  h.position_sigma_m = std::sqrt(est.pose_cov.diagonal().head<3>().maxCoeff());
  h.attitude_sigma_rad = std::sqrt(est.pose_cov.diagonal().tail<3>().maxCoeff());
  health_pub_.publish(h);
  last_health_us_ = h.utime;
}

LocalizationTaskConfig localization_task_config(const AppConfig& cfg) {
  LocalizationTaskConfig c;
  c.filter.T_body_cam = cfg.T_body_cam;
  c.handrail.wall_offset_m = cfg.estimator.handrail.bar_center_offset_m;
  return c;
}

LocalizerReport localizer_report(const LocalizationTask& task) {
  LocalizerReport r;
  r.task = task.counters();
  const loc::LocalizationFilter& f = task.filter();
  const loc::FilterCounters& c = f.counters();
  using loc::ImuStatus;
  using loc::MeasurementKind;
  using loc::UpdateStatus;
  r.imu_propagated = c.count(ImuStatus::kPropagated);
  r.imu_gaps_bridged = c.count(ImuStatus::kGapBridged);
  r.imu_gaps_lost = c.count(ImuStatus::kGapLost);
  r.imu_rejected = c.count(ImuStatus::kRejectedNotFinite) +
                   c.count(ImuStatus::kRejectedOutOfRange) +
                   c.count(ImuStatus::kRejectedOutOfOrder) + c.count(ImuStatus::kRejectedBadConfig);
  r.gp_accepted = c.count(MeasurementKind::kGpPose, UpdateStatus::kAccepted) +
                  c.count(MeasurementKind::kGpPose, UpdateStatus::kInitialized);
  r.gp_rejected_gate = c.count(MeasurementKind::kGpPose, UpdateStatus::kRejectedGate);
  r.gp_rejected_jump = c.count(MeasurementKind::kGpPose, UpdateStatus::kRejectedJump);
  r.gp_relocalized = c.count(MeasurementKind::kGpPose, UpdateStatus::kRelocalized);
  r.gp_rejected_other =
      c.rejected(MeasurementKind::kGpPose) - r.gp_rejected_gate - r.gp_rejected_jump;
  for (const MeasurementKind k :
       {MeasurementKind::kHandrailEnds, MeasurementKind::kHandrailNoEnd}) {
    r.handrail_rejected_gate += c.count(k, UpdateStatus::kRejectedGate);
    r.handrail_rejected_other += c.rejected(k) - c.count(k, UpdateStatus::kRejectedGate);
    r.handrail_map_sightings +=
        c.count(k, UpdateStatus::kMapSighting) + c.count(k, UpdateStatus::kMapInitialized);
  }
  r.handrail_accepted = c.count(MeasurementKind::kHandrailEnds, UpdateStatus::kAccepted);
  r.handrail_no_end_accepted = c.count(MeasurementKind::kHandrailNoEnd, UpdateStatus::kAccepted);
  r.features_gated = c.features_gated;
  r.map_resets = c.map_resets;
  r.initialized = f.initialized();
  r.map_valid = f.handrail_map().valid;
  r.map_surveyed = f.handrail_map().surveyed;
  r.handrail_holding = f.handrail_holding();
  return r;
}

}  // namespace fsw_app
