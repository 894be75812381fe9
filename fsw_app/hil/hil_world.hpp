#pragma once
// The world of a hardware-in-loop run on the simulated HAL (host only): a
// free-flyer carrying the camera, which renders the scenario's scene from
// the flyer's true pose every frame; the two AX-12A servos and the gripper
// board as simulated devices on ptys (the arm task drives them through the
// real drivers); and the contact between gripper and handrail: fingers that
// close within reach of the bar stop on it, and a closed grip holds the
// robot to the bar, the joints then turning the body about it.
// It follows BODY_VELOCITY_COMMAND over LCM; its navigation sensors
// (hil_sensors.hpp) publish IMU_SAMPLE, GP_POSE and, for scoring only,
// TRUTH_POSE: the robot's pose (ROBOT_POSE) is the localization task's.
#include <Eigen/Geometry>
#include <atomic>
#include <cstdint>
#include <mutex>
#include <string>

#include "fsw_app/app_config.hpp"
#include "fsw_app/lcm_hub.hpp"
#include "fsw_app/periodic_thread.hpp"
#include "hal/clock.hpp"
#include "hil_sensors.hpp"
#include "hrp/body_velocity_command_t.hpp"
#include "sim_hal/flyer.hpp"
#include "sim_hal/scenario.hpp"
#include "sim_hal/sim_gripper.hpp"
#include "sim_hal/sim_servo_bus.hpp"
#include "sim_hal/simulated_camera.hpp"

namespace fsw_app {

// The start pose of run `seed`: the scenario's first camera pose turned
// into a body pose, then moved by up to +-10 cm across the wall, 0.9 to
// 1.1 m out from it, and turned by up to +-8 deg in yaw and +-4 deg in
// pitch and roll.
Eigen::Isometry3d hil_start_pose(const sim_hal::Scenario& scenario,
                                 const Eigen::Isometry3d& T_body_cam, std::uint64_t seed);

struct HilStats {
  bool locked = false;          // the gripper holds the robot to a bar
  double grasp_error_m = -1.0;  // grasp point to bar centre line when the grip closed
  // Along the bar from its middle (the point the perch aims at), signed
  // toward the bar's second end; when the grip closed.
  double grasp_along_m = 0.0;
  std::int64_t locked_at_us = 0;
  LocalizationScore localization;  // the filter's and the GP's errors
};

// A camera that stops delivering (--fault camera-silent, camera-lost on
// the in-process paths): between the camera and its listener, every frame
// is swallowed until the cut's end, as from a camera that went quiet.
class CameraCut final : public hal::DepthDataListener {
 public:
  CameraCut(const hal::Clock& clock, hal::DepthDataListener& listener)
      : clock_(clock), listener_(listener) {}
  void on_new_data(const hal::DepthFrame& frame) override {
    if (clock_.now_us() < cut_until_us_.load()) {
      swallowed_.fetch_add(1);
      return;
    }
    listener_.on_new_data(frame);
  }
  void cut_until(std::int64_t t_us) { cut_until_us_ = t_us; }
  std::uint64_t swallowed() const { return swallowed_.load(); }

 private:
  const hal::Clock& clock_;
  hal::DepthDataListener& listener_;
  std::atomic<std::int64_t> cut_until_us_{0};
  std::atomic<std::uint64_t> swallowed_{0};
};

class HilWorld final : public sim_hal::CameraPoseSource, public sim_hal::FrameTamper {
 public:
  HilWorld(LcmHub& hub, const sim_hal::Scenario& scenario, const AppConfig& config,
           const Eigen::Isometry3d& T_world_body_start, std::uint64_t seed, const hal::Clock& clock,
           const HilSensorParams& sensors = HilSensorParams{});
  ~HilWorld() override;

  bool start(std::string* error);  // the devices' ptys and the physics thread
  void stop();

  const std::string& servo_path() const { return servos_.path(); }
  const std::string& gripper_path() const { return gripper_.path(); }
  sim_hal::SimulatedCamera& camera() { return camera_; }
  sim_hal::SimServoBus& servos() { return servos_; }
  sim_hal::SimGripperBoard& gripper() { return gripper_; }

  Eigen::Isometry3d T_world_cam(std::int64_t now_us) override;
  void tamper(std::int64_t now_us, hal::DepthFrame* frame,
              std::vector<hal::DepthPoint>* points) override;

  // Faults: the camera sees nothing until then; the next n frames are
  // corrupt (wrong size, dropped by the camera task).
  void occlude_until(std::int64_t t_us) { occluded_until_us_ = t_us; }
  void corrupt_next_frames(int n) { corrupt_frames_ = n; }
  bool occluded(std::int64_t now_us) const { return now_us < occluded_until_us_.load(); }
  HilSensors& sensors() { return sensors_; }

  Eigen::Isometry3d body_pose() const;
  // The grasp point's distance from the target bar's centre line now.
  double gripper_to_bar_m() const;
  HilStats stats() const;
  const sim_hal::Handrail& target_handrail() const { return scenario_.scene.handrails[target_]; }

 private:
  void physics_tick();  // 100 Hz
  void physics_step(double dt_s, std::int64_t now_us);
  arm::JointAngles joint_angles() const;
  // Perpendicular distance to the bar's centre line and the position along
  // it (0 at end 0).
  void bar_distance(const Eigen::Vector3d& p, double* perp_m, double* along_m) const;

  LcmHub& hub_;
  const sim_hal::Scenario& scenario_;
  AppConfig config_;
  const hal::Clock& clock_;
  std::size_t target_ = 0;
  int handrail_counts_ = 0;  // where the fingers stop on this bar
  sim_hal::SimServoBus servos_;
  sim_hal::SimGripperBoard gripper_;
  sim_hal::SimulatedCamera camera_;
  Mailbox<hrp::body_velocity_command_t> command_box_;
  mutable std::mutex mutex_;  // flyer, stats, lock
  sim_hal::SimFlyer flyer_;
  HilStats stats_;
  Eigen::Isometry3d T_world_grasp_lock_ = Eigen::Isometry3d::Identity();
  std::atomic<std::int64_t> occluded_until_us_{0};
  std::atomic<int> corrupt_frames_{0};
  std::int64_t last_tick_us_ = 0;  // the physics thread's
  std::uint64_t ticks_ = 0;
  HilSensors sensors_;
  PeriodicThread physics_;  // last: stopped before the members it uses go
};

}  // namespace fsw_app
