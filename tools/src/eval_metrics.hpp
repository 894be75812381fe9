#pragma once
// Scoring detections against the simulator's ground truth, for hreval.
#include <cstdint>
#include <map>
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

// The definition of a frame with a target: a handrail at least 35 %
// visible whose visible part's middle is 0.25 to 1.5 m from the camera
// (nearer, the detector's wall fills the view; farther, the bar is a few
// pixels); among several, the one nearest the gripper angle. -1 if none.
int target_handrail_in_reach(const sim_hal::FrameTruth& truth, double gripper_angle_rad);
// The far end of that reach: the visible part's middle this far away.
constexpr double kReachMaxM = 1.5;

FrameErrors score_detection(const estimator::HandrailDetection& d, const sim_hal::HandrailTruth& t);

// The handrail a detection is scored against. With several handrails in
// view the gripper could take more than the one nearest its angle (the
// Columbus module models three dozen of its own, many beside and parallel
// to the scenario's rails). A detection that matches (is_correct) any
// handrail in view, however little of it shows, that lies within 45 deg
// of the gripper angle (the detector's own selection window) or no further
// from it than the target (within a degree: parallel to it) is scored
// against that one (the nearest, if several): it found a handrail the
// gripper can take. The visibility rules say when a frame expects a
// detection (`target`), not whether a detection is right; but for the
// in-reach figures (`in_reach`, `target` from target_handrail_in_reach)
// the handrail found must lie within reach too (its visible part's middle
// no further than kReachMaxM; nearer than 0.25 m is within reach). Otherwise
// `target`: a detection of a handrail across the gripper, or out of reach,
// stays false.
int scored_target(const estimator::HandrailDetection& d, const sim_hal::FrameTruth& truth,
                  double gripper_angle_rad, int target, bool in_reach);

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
  // The nearest-rank percentile (p in [0, 100]); NaN when empty.
  double percentile(double p) const;
  std::string mean_sd(int decimals = 1) const;  // "m +- s", or "-" when empty
};

// The state confusion matrix's rows (what is in view) and columns (what
// the detector said).
enum ConfusionRow { kTruthBE, kTruthOE, kTruthNE, kTruthNH, kConfusionRows };
enum ConfusionColumn { kSaidBE, kSaidOE, kSaidNE, kSaidFalse, kSaidNH, kConfusionColumns };

// Everything hreval accumulates for one group of frames and one method.
struct Tally {
  int frames = 0;
  int target_frames = 0;  // frames with a handrail to take
  int found = 0;          // frames where the detector reported a handrail
  int correct = 0;        // ... and it was the target
  int false_found = 0;    // ... and it was not (or there was none)
  int state_checked = 0;
  int state_right = 0;
  // The same detection rate over the frames with a target
  // (target_handrail_in_reach).
  int reach_target_frames = 0;
  int reach_correct = 0;
  Stats x, y, z, perpendicular, roll, pitch, yaw, axis, normal, beam, time_ms;
  // The two pose errors the targets name, over the correct detections alone (the
  // ones above count every detection of a frame with a target, as the
  // paper's Figure 15 does).
  Stats correct_perpendicular, correct_axis;
  // Why each frame came out as it did: FOUND (the target, or a handrail in
  // view), FALSE (a detection that is not), or the detector's status
  // (NO_PLANE, NO_CANDIDATES, NO_LINE with its first line rejection, ...).
  std::map<std::string, int> reasons;
  // Frames with a target whose target was not found, and frames with a
  // false detection (frame indices).
  std::vector<std::uint64_t> missed_frames, false_frames;
  // Rows: the target's state from the truth (NH: no target); columns: the
  // state reported with a correct detection, a false one, or none.
  int confusion[kConfusionRows][kConfusionColumns] = {};

  // `target` as target_handrail picks it, `reach_target` as
  // target_handrail_in_reach does.
  void add(const estimator::HandrailDetection& d, const sim_hal::FrameTruth& truth, int target,
           int reach_target);
  void merge(const Tally& other);
  double rate(int n, int of) const { return of ? 100.0 * n / of : 0.0; }
};

// "25: 0-4, 9, 12-30" (the count, then ranges) from sorted frame indices,
// at most max_ranges ranges and then how many frames more.
std::string frame_ranges(const std::vector<std::uint64_t>& frames, std::size_t max_ranges = 12);

}  // namespace tools
