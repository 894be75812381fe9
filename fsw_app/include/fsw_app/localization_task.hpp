#pragma once
// The localization task: the error-state EKF (estimator/localization) fed
// from LCM, publishing the robot's pose the other tasks fly on.
//   in:  IMU_SAMPLE (every sample, a fixed queue of 32: 0.5 s at 62.5 Hz),
//        GP_POSE (every pose, a queue of 4), HANDRAIL_ESTIMATE (the newest)
//   out: ROBOT_POSE with the filter's pose, velocity, covariance and source
//        FILTER, after every cycle in which the filter's time advanced;
//        LOCALIZATION_HEALTH once a second.
// One cycle (100 Hz): the queued IMU samples in order, then the GP poses,
// then a new handrail estimate (the filter applies each at its capture
// time), then the pose. Samples missing by the IMU's counter are counted;
// the filter bridges or flags the gap by its own rule. Before the filter is
// initialised (its first GP pose) nothing is published on ROBOT_POSE. The
// filter and every message are built once: a cycle allocates nothing.
// step() is the cycle without the thread, for tests in lock step.
#include <cstdint>
#include <memory>

#include "estimator/localization/localization_filter.hpp"
#include "fsw_app/app_config.hpp"
#include "fsw_app/bar_length_tally.hpp"
#include "fsw_app/handrail_measurement.hpp"
#include "fsw_app/lcm_hub.hpp"
#include "fsw_app/periodic_thread.hpp"
#include "hal/clock.hpp"
#include "hrp/gp_pose_t.hpp"
#include "hrp/handrail_estimate_t.hpp"
#include "hrp/imu_sample_t.hpp"
#include "hrp/localization_health_t.hpp"
#include "hrp/robot_pose_t.hpp"

namespace fsw_app {

struct LocalizationTaskConfig {
  estimator::localization::LocalizationConfig filter;
  HandrailFeatureModel handrail;
  double rate_hz = 100.0;
  // While the handrail holds the pose (a handrail update accepted within the
  // filter's handrail_hold_s), GP poses are held off, not applied: the
  // handrail map is then the reference, and the GP's bias, which drifts
  // against the map by centimetres over a minute, would pull the pose off
  // the bar (the dynamic test showed 8 mm across the bar with it applied).
  // When the handrail is lost the hold lapses and the GP is used again.
  bool gp_while_handrail_holds = false;
};

struct LocalizationTaskCounters {
  std::uint64_t imu_in = 0, gp_in = 0, handrail_in = 0;
  std::uint64_t gp_held_off = 0;   // GP poses not applied: the handrail held the pose
  std::uint64_t imu_seq_gaps = 0;  // samples missing by the IMU's counter
  std::uint64_t imu_queue_overflows = 0;
  std::uint64_t handrail_unusable = 0;  // NH, deadline, nothing in view
  // Handrail updates the filter accepted, by the state it took them in
  // (BE, OE, NE), and OE estimates taken as NE for want of a known bar
  // length (bar_length_tally.hpp).
  std::uint64_t handrail_accepted_be = 0, handrail_accepted_oe = 0, handrail_accepted_ne = 0;
  std::uint64_t handrail_oe_as_ne = 0;
  std::uint64_t poses_published = 0;
  // GP poses the filter accepted after the handrail had held the pose and
  // stopped holding it: the fall-back on the GP when the handrail is lost.
  std::uint64_t gp_fallback_accepted = 0;
  // The filter's world position sigma (largest axis) in the newest pose
  // published, and the smallest published while the handrail held the pose
  // (-1: never). It includes the map's own uncertainty, so the handrail
  // does not take it below what the GP knew when the map was made.
  double position_sigma_m = -1.0;
  double position_sigma_held_min_m = -1.0;
  // Relative to the handrail map, across the bar (the larger of its
  // wall-normal and sideways axes): what the handrail measures, which grows
  // once it is lost (-1: no map).
  double across_bar_sigma_m = -1.0;
  double across_bar_sigma_held_min_m = -1.0;
};

// What the run summary reports of the task: the filter's verdicts on its
// inputs, summed over the reasons that matter.
struct LocalizerReport {
  LocalizationTaskCounters task;
  std::uint32_t imu_propagated = 0, imu_gaps_bridged = 0, imu_gaps_lost = 0, imu_rejected = 0;
  std::uint32_t gp_accepted = 0, gp_rejected_gate = 0, gp_rejected_jump = 0, gp_relocalized = 0,
                gp_rejected_other = 0;
  std::uint32_t handrail_accepted = 0, handrail_no_end_accepted = 0, handrail_rejected_gate = 0,
                handrail_rejected_other = 0, handrail_map_sightings = 0;
  std::uint32_t features_gated = 0, map_resets = 0;
  bool initialized = false, map_valid = false, map_surveyed = false, handrail_holding = false;
};

class LocalizationTask {
 public:
  LocalizationTask(LcmHub& hub, const LocalizationTaskConfig& cfg, const hal::Clock& clock);
  ~LocalizationTask();
  void start();
  void stop();
  // One cycle: inputs into the filter, ROBOT_POSE out.
  void step();
  void publish_health();

  // The handrail's surveyed world pose as the filter's map (before start()):
  // the filter's verdict on it (handrail_map.hpp's check_survey()).
  estimator::localization::UpdateStatus set_handrail_survey(
      const estimator::localization::HandrailMap& survey);

  const estimator::localization::LocalizationFilter& filter() const { return *filter_; }
  LocalizationTaskCounters counters() const;
  const hrp::robot_pose_t& last_pose() const { return pose_; }

 private:
  void take_handrail(const hrp::handrail_estimate_t& e);
  void fill_pose();
  void note_sigmas();

  LcmHub& hub_;
  LocalizationTaskConfig cfg_;
  const hal::Clock& clock_;
  std::unique_ptr<estimator::localization::LocalizationFilter> filter_;
  std::unique_ptr<estimator::localization::HandrailMeasurement> measurement_;
  BarLengthTally bar_length_;  // the bar's length from BE estimates, for OE ones
  MessageQueue<hrp::imu_sample_t, 32> imu_queue_;
  MessageQueue<hrp::gp_pose_t, 4> gp_queue_;
  Mailbox<hrp::handrail_estimate_t> handrail_box_;
  Publisher<hrp::robot_pose_t> pose_pub_;
  Publisher<hrp::localization_health_t> health_pub_;
  hrp::imu_sample_t imu_{};
  hrp::gp_pose_t gp_{};
  hrp::handrail_estimate_t handrail_{};
  hrp::robot_pose_t pose_{};
  hrp::localization_health_t health_{};
  std::uint64_t handrail_seen_ = 0;
  std::int64_t last_imu_seq_ = -1;
  std::int64_t published_t_us_ = 0;
  Eigen::Vector3d last_omega_body_ = Eigen::Vector3d::Zero();
  std::int64_t last_health_us_ = 0;
  std::atomic<std::uint64_t> imu_in_{0}, gp_in_{0}, gp_held_off_{0}, handrail_in_{0},
      imu_seq_gaps_{0}, handrail_unusable_{0}, poses_published_{0}, gp_fallback_accepted_{0},
      handrail_accepted_be_{0}, handrail_accepted_oe_{0}, handrail_accepted_ne_{0},
      handrail_oe_as_ne_{0};
  std::atomic<double> position_sigma_m_{-1.0}, position_sigma_held_min_m_{-1.0},
      across_bar_sigma_m_{-1.0}, across_bar_sigma_held_min_m_{-1.0};
  bool handrail_has_held_ = false;
  PeriodicThread thread_;  // last: stopped before the members it uses go
};

// The task's configuration from the application's: the camera mount and
// the handrail's geometry.
LocalizationTaskConfig localization_task_config(const AppConfig& cfg);
// After stop().
LocalizerReport localizer_report(const LocalizationTask& task);

}  // namespace fsw_app
