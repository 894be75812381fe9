#pragma once
// The perch sequence's tunables. Defaults suit the 24 cm prototype arm,
// the Baby Orangutan gripper board with its encoder in counts from the open
// stop, and a 20 Hz step.
#include <cstdint>

#include "arm/arm_model.hpp"

namespace arm {

struct StateTimeoutsMs {
  int init = 3000;
  int deploying = 8000;     // 90 deg at 1 rad/s is 1.6 s: room for a slow servo
  int calibrating = 10000;  // the board drives slowly to the open stop
  int opening = 5000;
  int gripper_open = 90000;  // the whole visual-servoing approach
  int closing = 5000;
  int grasp_check = 1500;
  int pan_tilt = 8000;
  int unperching = 5000;
  int backing_off = 30000;
  int stowing = 10000;
};

struct PerchConfig {
  ArmGeometry geometry;
  StateTimeoutsMs timeouts;
  double joint_speed_rad_s = 1.0;      // AX-12A limit in the flown arm: 20 rpm = 2.1 rad/s
  double joint_tolerance_rad = 0.035;  // 2 deg: "at the goal"
  // Pan / tilt while perched, within the joint limits.
  JointLimits perched_tilt{-1.4, 1.4};
  JointLimits perched_pan{-1.4, 1.4};
  double open_speed = 0.8, close_speed = 0.6, stow_speed = 0.5;  // fractions of full drive
  int close_current_limit_ma = 800;
  int open_done_counts = 80;         // open: at or below this
  int stow_gripper_counts = 2000;    // fingers nearly closed for stowing
  int stow_gripper_tolerance = 120;  // counts
  // Grasp check: a handrail in hand holds between these encoder counts (the
  // ISS bar and the round bar both fall inside); beyond the upper bound the
  // fingers closed on nothing; below the lower they stopped on something
  // wider than a handrail (a box edge, a cable bundle).
  int grasp_min_counts = 1000;
  int grasp_max_counts = 2600;
  int grasp_min_current_ma = 400;  // holding force present
  int grasp_settle_ms = 200;       // the hold must last this long
  std::uint8_t max_grasp_attempts = 3;
  int handrail_lost_ms = 1500;  // approach: no estimate this long is a loss
  // Approach: the perch manager without a usable robot pose this long (it
  // holds the robot still meanwhile) aborts the perch, the arm folded.
  int pose_lost_ms = 2000;
  // Approach: no camera frame this long (the perch manager holds the robot
  // still meanwhile) aborts the perch, the arm folded. 3 s lets the USB
  // driver ride out what it recovers from on its own: its silence window
  // (0.5 s) and first rungs (clear halt, re-initialise), or a cable
  // reseated; an open gripper held still near the wall costs nothing
  // meanwhile. While frames are missing, handrail_lost_ms waits: no frame
  // is not "no handrail", and it counts again from the frames' return.
  int camera_lost_ms = 3000;
  std::uint8_t io_failures_to_fault = 2;  // consecutive failed reads before a fault
};

}  // namespace arm
