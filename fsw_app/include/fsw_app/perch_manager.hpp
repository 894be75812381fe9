#pragma once
// The perch manager: visual servoing toward the estimator's target pose,
// in step with the arm's perch sequence, and the approach status the arm
// waits on.
//   arm DEPLOYING .. OPENING: fly to a stand-off pose out from the target
//     along the wall normal;
//   GRIPPER_OPEN: close in, moving toward the wall only as fast as the
//     robot is lined up across it; "at target" once within tolerance for a
//     few cycles. Proportional plus a bounded integral near the goal (the
//     disturbances are slow pushes);
//   CLOSING, GRASP_CHECK: keep station on the grasp pose;
//   PERCHED, FAULT and the rest: hold;
//   BACKING_OFF: straight out along the wall normal, "backed off" once clear.
// Whatever the arm's state, the robot holds still (zero velocity) unless
// its ROBOT_POSE is the filter's, not marked lost, at most
// pose_max_age_ms old and no more uncertain than pose_max_position_sigma_m
// and pose_max_attitude_sigma_rad; APPROACH_STATUS says since when it has had none,
// and the arm aborts the perch (POSE_LOST, arm folded) when that lasts
// longer than its pose_lost_ms. Likewise from DEPLOYING to GRIPPER_OPEN
// (where it flies on the sightings) it holds while frames are late, no
// estimate of any kind for more than camera_hold_frames frame periods;
// APPROACH_STATUS says since when, and the arm aborts (CAMERA_LOST, arm
// folded) past its camera_lost_ms. Frames again: the approach resumes.
// ApproachController is the logic (pure, time injected); PerchManager wires
// it to LCM on a thread.
#include <Eigen/Geometry>
#include <cstdint>

#include "fsw_app/app_config.hpp"
#include "fsw_app/lcm_hub.hpp"
#include "fsw_app/periodic_thread.hpp"
#include "hal/clock.hpp"
#include "hrp/approach_status_t.hpp"
#include "hrp/arm_state_t.hpp"
#include "hrp/body_velocity_command_t.hpp"
#include "hrp/handrail_estimate_t.hpp"
#include "hrp/robot_pose_t.hpp"

namespace fsw_app {

// Position errors are the grasp point's: body to target would hide the
// lever of the body's attitude error over the 0.4 m to the grasp point.
struct ApproachOutput {
  hrp::body_velocity_command_t velocity{};
  hrp::approach_status_t status{};
};

// The camera as the manager judges it (approach_status_t's CAMERA_*).
enum class CameraLiveness : std::int8_t {
  kStreaming = hrp::approach_status_t::CAMERA_STREAMING,
  kLate = hrp::approach_status_t::CAMERA_LATE,
  kNotSeen = hrp::approach_status_t::CAMERA_NOT_SEEN,
};
const char* to_string(CameraLiveness liveness);

// The camera over a run, as the manager saw it (for the run's summary).
struct CameraWatch {
  CameraLiveness liveness = CameraLiveness::kNotSeen;  // at the last cycle
  std::uint32_t late_spells = 0;                       // times frames went late after streaming
  std::int64_t longest_frame_gap_us = 0;               // between successive frames' capture times
  std::int64_t late_us = 0;                            // total time late after the first frame
};

class ApproachController {
 public:
  // p_body_grasp: the grasp point in the body frame, arm in the grip posture.
  ApproachController(const ApproachConfig& cfg, const Eigen::Vector3d& p_body_grasp)
      : cfg_(cfg), p_body_grasp_(p_body_grasp) {}

  // A new estimate (call once per estimate).
  void on_estimate(const hrp::handrail_estimate_t& estimate);
  // One control cycle.
  ApproachOutput step(std::int64_t now_us, const hrp::robot_pose_t* pose, std::int8_t arm_state);

  bool has_target() const { return have_target_; }
  const CameraWatch& camera_watch() const { return watch_; }
  const Eigen::Isometry3d& target() const { return T_world_target_; }
  const Eigen::Isometry3d& handrail() const { return T_world_handrail_; }

 private:
  // Whether the robot may fly on this pose now.
  bool pose_usable(std::int64_t now_us, const hrp::robot_pose_t* pose) const;
  // The camera's liveness, frame age and since when frames are late, into
  // the status.
  void judge_camera(std::int64_t now_us, std::int64_t dt_us, hrp::approach_status_t* status);
  // Velocity toward `goal`, limited.
  // With approach_axis, motion along it waits for the lateral error.
  void servo_to(const Eigen::Isometry3d& T_world_body, const Eigen::Isometry3d& goal,
                ApproachOutput* out, double dt_s, const Eigen::Vector3d* approach_axis);

  ApproachConfig cfg_;
  Eigen::Vector3d p_body_grasp_;
  bool have_target_ = false;
  Eigen::Isometry3d T_world_target_ = Eigen::Isometry3d::Identity();
  Eigen::Isometry3d T_world_handrail_ = Eigen::Isometry3d::Identity();
  std::int64_t handrail_seen_us_ = -1;
  std::int64_t pose_unusable_since_us_ = -1;
  std::int64_t frame_seen_us_ = -1;  // capture time of the newest estimate of any kind
  std::int64_t camera_late_since_us_ = -1;
  CameraWatch watch_;
  int settled_ = 0;
  std::int64_t last_step_us_ = 0;
  Eigen::Vector3d integral_ = Eigen::Vector3d::Zero();
  bool backing_off_ = false;
  double back_off_start_m_ = 0.0;  // distance out from the bar when the back-off began
};

class PerchManager {
 public:
  PerchManager(LcmHub& hub, const ApproachConfig& cfg, const Eigen::Vector3d& p_body_grasp,
               const hal::Clock& clock, double rate_hz);
  ~PerchManager();
  void start();
  void stop();
  void cycle();
  const ApproachController& controller() const { return controller_; }

 private:
  LcmHub& hub_;
  const hal::Clock& clock_;
  ApproachController controller_;
  std::int64_t period_us_;
  Mailbox<hrp::handrail_estimate_t> estimate_box_;
  Mailbox<hrp::robot_pose_t> pose_box_;
  Mailbox<hrp::arm_state_t> arm_box_;
  Publisher<hrp::body_velocity_command_t> velocity_pub_;
  Publisher<hrp::approach_status_t> status_pub_;
  hrp::handrail_estimate_t estimate_{};
  hrp::robot_pose_t pose_{};
  hrp::arm_state_t arm_{};
  std::uint64_t estimate_seen_ = 0;
  PeriodicThread thread_;  // last: stopped before the members it uses go
};

}  // namespace fsw_app
