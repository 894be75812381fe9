#pragma once
// Every line the detector put to its tests in the last frame, in order, with
// the verdict each got: what a frame's first rejection (counts) does not say
// when the line that won is not the one expected, or the one expected was
// never tested (a search that settled on another line first). Off by
// default; when on, a fixed buffer in the detector fills as the searches go
// (no allocation, no work beyond a copy per tested line). For diagnostics
// (hrdetect --lines), not for the flight's decisions.
#include <cstdint>

#include <Eigen/Core>

#include "estimator/types.hpp"

namespace estimator {

struct LineTraceEntry {
  std::uint8_t search = 0;      // the frame's mount search it came from, 0 first
  float search_mount_m = 0.0f;  // that search's mount, from the dominant plane
  LineVerdict verdict = LineVerdict::kAccepted;
  std::uint32_t inliers = 0;
  // Set once the line had a centre line (every verdict after
  // TOO_FEW_POINTS and NO_CENTER_LINE).
  bool has_center_line = false;
  Eigen::Vector3f middle_cam = Eigen::Vector3f::Zero();  // visible middle
  Eigen::Vector3f axis_cam = Eigen::Vector3f::Zero();
  float visible_length_m = 0.0f;
  // Set once the front-height test seated it on a mount (every verdict
  // after WRONG_HEIGHT); then the front stands front_height_m above that
  // mount, else above the searched one.
  bool seated = false;
  float front_height_m = 0.0f;
  float mount_m = 0.0f;  // the mount seated on, from the dominant plane
  // Set once its ends were walked (the verdicts from RAMP_END on, and
  // ACCEPTED); then which ends were seen.
  bool ends_walked = false;
  bool end_seen[2] = {false, false};
};

struct LineTrace {
  // Lines a frame can test: line_attempts searches of two candidates on
  // each of up to kMaxMountHypotheses + 1 mounts, with the defaults; more
  // are counted, not kept.
  static constexpr std::uint32_t kMaxEntries = 96;
  LineTraceEntry entries[kMaxEntries];
  std::uint32_t count = 0;
  std::uint32_t dropped = 0;

  void clear() {
    count = 0;
    dropped = 0;
  }
  void push(const LineTraceEntry& e) {
    if (count < kMaxEntries) {
      entries[count++] = e;
    } else {
      ++dropped;
    }
  }
};

}  // namespace estimator
