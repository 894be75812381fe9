#pragma once
// fsw_app's one configuration file (JSON): LCM URL, camera use case and
// extrinsics, estimator thresholds, arm geometry, perch sequence, ports and
// rates, and the approach. Every key is optional (defaults below and in
// fsw_app/config/fsw_app.json); an unknown key, a wrong type or a value out
// of range stops start-up with "FILE:LINE: key: what is wrong".
#include <Eigen/Geometry>
#include <cstdint>
#include <string>

#include "arm/perch_config.hpp"
#include "arm_io/ax12_joints.hpp"
#include "estimator/config.hpp"

namespace fsw_app {

// The longest camera serial number: the Pico Flexx protocol's serial field
// (drivers/pico_flexx/PROTOCOL.md; fsw_app's camera set-up checks the two
// agree).
constexpr std::size_t kCameraSerialChars = 16;

struct PortsConfig {
  std::string servo_port = "/dev/ttyUSB0";
  std::uint32_t servo_baud = 1000000;
  std::uint32_t servo_return_delay_us = 500;
  std::uint32_t servo_margin_us = 3000;
  std::string gripper_port = "/dev/ttyO1";
  std::uint32_t gripper_baud = 115200;
  std::uint32_t gripper_margin_us = 5000;
  // The board stops its motor and goes to safe start when no valid command
  // came for this long (sent to the board at start; 0 turns it off).
  std::uint32_t gripper_serial_timeout_ms = 500;
};

struct ApproachConfig {
  double standoff_m = 0.20;     // first to this distance out from the grasp pose
  double max_speed_mps = 0.10;  // the flyer's approach speed limit
  double max_rate_rps = 0.25;
  double gain_per_s = 1.5;  // velocity = gain * error (+ integral), then limited
  double integral_gain_per_s2 = 0.4;
  double brake_mps2 = 0.03;         // speed limited to what this stops in the distance left
  double settle_speed_mps = 0.005;  // "at target" also needs the robot this slow
  double position_tolerance_m = 0.005;
  double angle_tolerance_rad = 0.05;
  double back_off_m = 0.25;  // after letting go
  int settle_cycles = 5;     // within tolerance this many cycles: at target
  // The robot flies only on a ROBOT_POSE from the filter, not marked lost,
  // and no older than this; otherwise it holds still (zero velocity). The
  // filter publishes with every IMU sample (62.5 Hz): 250 ms is 15 missed.
  int pose_max_age_ms = 250;
  // Nor on a pose the filter itself no longer vouches for: its position
  // 1-sigma (the square root of the position block's trace, the radial
  // spread) or its attitude's above these. The manager flies toward
  // sightings placed in the world with the same poses, so an offset common
  // to both cancels and a GP-limited filter perches well: the GP may be
  // off by up to a metre (its claimed sigma 0.6 m per axis, 1.04 m radial,
  // at fsw_app's largest --gp-error). The bounds catch a filter that has
  // coasted on the IMU alone until it no longer knows where the robot is.
  double pose_max_position_sigma_m = 1.5;
  double pose_max_attitude_sigma_rad = 0.5236;  // 30 deg
  // The robot flies toward the bar only while frames arrive: with none
  // for more than this many frame periods (the use case's) it holds
  // still. 3: a single frame refused or dropped by the estimator, plus an
  // estimate's latency (up to a frame period), is ridden out; two missed
  // in a row mean the target is being flown on stale sightings (at 5 fps,
  // 0.6 s, 6 cm at the approach speed limit). The arm's camera_lost_ms
  // ends the perch if it lasts.
  int camera_hold_frames = 3;
  // The camera's frame period, from the use case at start-up (not a key).
  std::int64_t frame_period_us = 200000;
};

struct AppConfig {
  std::string lcm_url = "udpm://239.255.76.67:7667?ttl=0";
  std::string use_case = "MODE_9_5FPS_2000";
  // The camera in the body frame. Default: on the aft face beside the arm,
  // looking aft; image y is body -z, so a handrail along body z runs along
  // the image's y axis (gripper angle 0).
  Eigen::Isometry3d T_body_cam = default_T_body_cam();
  // --hal real: the Pico Flexx with this serial number (empty: the first
  // one found on the bus).
  std::string camera_serial;
  estimator::DetectorConfig estimator;
  arm::PerchConfig perch;  // includes the arm geometry
  arm_io::JointServoConfig servos;
  PortsConfig ports;
  ApproachConfig approach;
  double arm_rate_hz = 20.0;
  // SCHED_FIFO priority of the arm's control loop (0: the normal
  // scheduler). On the robot the servos' replies and the gripper board's
  // serial timeout should not wait behind the estimator; off by default
  // until measured on the BeagleBone's kernel (the summary reports the
  // loop's longest gap either way).
  int arm_rt_priority = 0;
  double manager_rate_hz = 20.0;

  static Eigen::Isometry3d default_T_body_cam();
};

bool load_app_config(const std::string& path, AppConfig* config, std::string* error);
bool parse_app_config(const std::string& text, const std::string& path, AppConfig* config,
                      std::string* error);

}  // namespace fsw_app
