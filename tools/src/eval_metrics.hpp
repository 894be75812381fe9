#pragma once
// Scoring detections against the simulator's ground truth, for hreval.
#include <string>
#include <vector>

#include "estimator/types.hpp"
#include "sim_hal/ground_truth.hpp"

namespace tools {

// Errors of one detection, in the true handrail's frame (x = wall normal,
// y = across the bar, z = along it), millimetres and degrees.
struct FrameErrors {
  double x_mm, y_mm, z_mm;  // z only meaningful when both ends are seen
  double perpendicular_mm;  // distance of the position from the true centre line
  double roll_deg, pitch_deg, yaw_deg;
  double axis_deg, normal_deg;
  double beam_mm;  // NaN unless both ends were seen
};

// The handrail the gripper should take: among those at least 30 % visible,
// the one whose image angle is nearest the gripper angle. -1 if none.
int target_handrail(const sim_hal::FrameTruth& truth, double gripper_angle_rad);

FrameErrors score_detection(const estimator::HandrailDetection& d, const sim_hal::HandrailTruth& t);

// A detection is correct when it lies within 5 cm of the target's centre
// line and within 15 deg of its direction.
bool is_correct(const FrameErrors& e);

// The state the detector should report from what is in view.
estimator::HandrailState expected_state(const sim_hal::HandrailTruth& t);

struct Stats {
  std::vector<double> values;
  void add(double v) { values.push_back(v); }
  double mean() const;
  double stddev() const;
  double median() const;
  std::string mean_sd(int decimals = 1) const;  // "m +- s", or "-" when empty
};

// Everything hreval accumulates for one group of frames and one method.
struct Tally {
  int frames = 0;
  int target_frames = 0;  // frames with a handrail to take
  int found = 0;          // frames where the detector reported a handrail
  int correct = 0;        // ... and it was the target
  int false_found = 0;    // ... and it was not (or there was none)
  int state_checked = 0;
  int state_right = 0;
  Stats x, y, z, perpendicular, roll, pitch, yaw, axis, normal, beam, time_ms;

  void add(const estimator::HandrailDetection& d, const sim_hal::FrameTruth& truth, int target);
  double rate(int n, int of) const { return of ? 100.0 * n / of : 0.0; }
};

}  // namespace tools
