#pragma once
// The hardware-in-loop world's navigation sensors and the localization
// score (host only). Driven by the world's physics tick with the flyer's
// true pose, it publishes
//   IMU_SAMPLE   the simulated IMU's samples (sim_hal/sim_imu.hpp), 62.5 Hz;
//   GP_POSE      the simulated general-purpose localizer's fixes when they
//                are delivered (sim_hal/sim_gp_localizer.hpp), ~1.5 Hz;
//   TRUTH_POSE   the true pose, source TRUTH, 50 Hz: for scoring and
//                watching only (no robot-side task subscribes to it);
// and scores the robot's pose: every ROBOT_POSE (the filter's) against the
// true pose at the time it holds for, and every GP fix against the truth at
// its capture, over the approach (from begin_scoring() until the grip
// closes) and at the grasp.
#include <Eigen/Geometry>
#include <array>
#include <cstdint>
#include <mutex>

#include "fsw_app/lcm_hub.hpp"
#include "fsw_app/localization_score.hpp"
#include "hrp/gp_pose_t.hpp"
#include "hrp/imu_sample_t.hpp"
#include "hrp/robot_pose_t.hpp"
#include "sim_hal/sim_gp_localizer.hpp"
#include "sim_hal/sim_imu.hpp"

namespace fsw_app {

struct HilSensorParams {
  sim_hal::ImuParams imu;
  sim_hal::GpLocalizerParams gp;
};
// The defaults with the GP's bias of this size (it claims a sigma per axis
// to match, 0.6 of it, at least 2 cm and 0.5 deg).
HilSensorParams hil_sensor_params(double gp_bias_m, double gp_bias_deg);

class HilSensors {
 public:
  HilSensors(LcmHub& hub, const HilSensorParams& params, std::uint64_t seed);

  // Every physics tick, with the true pose and velocities (world frame).
  void on_tick(std::int64_t now_us, const Eigen::Isometry3d& T_world_body,
               const Eigen::Vector3d& v_world_mps, const Eigen::Vector3d& w_world_rps,
               bool publish_truth);
  void begin_scoring();
  // The grip closed: the errors now are the grasp's; scoring ends.
  void mark_grasp();
  LocalizationScore score() const;
  // Faults: the IMU silent for a while; the GP jumping by dp from now on.
  void silence_imu_until(std::int64_t t_us) { imu_silent_until_us_ = t_us; }
  void jump_gp(const Eigen::Vector3d& dp_world_m);

 private:
  struct TruthSample {
    std::int64_t t_us = 0;
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  };
  // The true pose nearest t_us in the ring; false when t_us is older.
  bool truth_at(std::int64_t t_us, Eigen::Isometry3d* T) const;
  void score_filter();

  LcmHub& hub_;
  sim_hal::SimImu imu_;
  sim_hal::SimGpLocalizer gp_;
  Publisher<hrp::imu_sample_t> imu_pub_;
  Publisher<hrp::gp_pose_t> gp_pub_;
  Publisher<hrp::robot_pose_t> truth_pub_;
  Mailbox<hrp::robot_pose_t> estimate_box_;
  hrp::imu_sample_t imu_msg_{};
  hrp::gp_pose_t gp_msg_{};
  hrp::robot_pose_t truth_msg_{}, estimate_{};
  std::array<sim_hal::ImuReading, sim_hal::SimImu::kMaxPerTick> readings_{};
  static constexpr int kTruthRing = 128;  // 1.28 s at 100 Hz
  std::array<TruthSample, kTruthRing> truth_{};
  int truth_next_ = 0, truth_count_ = 0;
  std::uint64_t estimate_seen_ = 0;
  std::int64_t imu_silent_until_us_ = 0;
  mutable std::mutex mutex_;  // score_
  bool scoring_ = false;
  double latest_filter_m_ = -1.0, latest_filter_deg_ = -1.0;
  double latest_gp_m_ = -1.0, latest_gp_deg_ = -1.0;
  LocalizationScore score_;
};

}  // namespace fsw_app
