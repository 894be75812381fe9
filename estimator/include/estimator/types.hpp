#pragma once
#include <Eigen/Core>
#include <cstdint>

namespace estimator {

// Handrail state by the number of end points seen (the paper's Figure 10).
enum class HandrailState : std::uint8_t {
  kNoHandrail,  // NH
  kBothEnds,    // BE
  kOneEnd,      // OE
  kNoEnd,       // NE
};
const char* to_string(HandrailState state);  // "NH", "BE", "OE", "NE"

// Why a frame produced what it did.
enum class DetectStatus : std::uint8_t {
  kFound,
  kEmptyFrame,      // no valid points in range
  kFrameTooLarge,   // larger than the size the detector was built for
  kNoPlane,         // no wall with enough support
  kNoCandidates,    // nothing passed the handrail tests
  kNoLine,          // no line of handrail length
  kDeadlineMissed,  // over the per-frame budget; result dropped
};
const char* to_string(DetectStatus status);

// Why the verification of a line candidate rejected it.
enum class LineVerdict : std::uint8_t {
  kAccepted,
  kTooFewPoints,    // its cluster is smaller than min_line_inliers
  kWrongHeight,     // its front face is not where the bar's is
  kNoCenterLine,    // degenerate points
  kTooShort,        // visible part shorter than shortest_partial_bar_m()
  kTooLong,         // longer than b_H,max
  kBeamLength,      // both ends seen, length outside b_H,min..b_H,max
  kNoMountBeside,   // the surface it would stand on is not beside it
  kRampEnd,         // a seen end comes down in a ramp, not at a leg
  kShallowProfile,  // seen from its side, no deeper than a cable (bar_profile.hpp)
  kSolidBelow,      // its side face reaches down where a grip needs space (bar_clearance.hpp)
  kTooFar,          // its visible middle lies beyond max_find_range_m
  kCrossesBar,      // the bar's front runs at an angle to the line (line_max_turn_deg)
  kNotOnTrack,      // on a face off the dominant plane, its mount's level runs on beside it
                    // (mount_beside.hpp)
  kNoTrackPastEnd,  // seated on a hidden track, yet past a seen end the face runs on level
                    // (track_past_end.hpp)
};
const char* to_string(LineVerdict verdict);

// A wall: n . p + d = 0 with |n| = 1 and the camera on the positive side
// (d > 0), so signed_distance > 0 means "in front of the wall".
struct Plane {
  Eigen::Vector3f normal = Eigen::Vector3f::Zero();
  float d = 0.0f;
  float signed_distance(const Eigen::Vector3f& p) const { return normal.dot(p) + d; }
};

// Per-stage counts, for debugging and the debug images.
struct StageCounts {
  std::uint32_t valid = 0;
  std::uint32_t plane_inliers = 0;
  std::uint32_t gap = 0;
  std::uint32_t cross = 0;
  std::uint32_t side = 0;
  std::uint32_t line = 0;
  std::uint32_t line_searches = 0;                       // Algorithm 2 runs
  std::uint32_t mount_hypotheses = 0;                    // mounts found
  std::uint32_t mounts_tried = 0;                        // searched, best first
  LineVerdict first_rejection = LineVerdict::kAccepted;  // of the best-supported line
};

struct HandrailDetection {
  DetectStatus status = DetectStatus::kEmptyFrame;
  HandrailState state = HandrailState::kNoHandrail;
  std::uint64_t frame_id = 0;
  std::int64_t capture_time_us = 0;
  // The fields below are meaningful only when status == kFound; they are
  // zeroed otherwise so no stale pose leaks into a "not found" result.
  Eigen::Vector3f p_cam_center = Eigen::Vector3f::Zero();    // on the bar's centre line
  Eigen::Matrix3f R_cam_handrail = Eigen::Matrix3f::Zero();  // columns: normal, y, axis
  Eigen::Vector3f ends_cam[2] = {Eigen::Vector3f::Zero(), Eigen::Vector3f::Zero()};
  bool end_seen[2] = {false, false};  // [0] at -axis, [1] at +axis
  float visible_length_m = 0.0f;      // extent of the line inliers
  float beam_length_m = 0.0f;         // between ends when both are seen
  // Both ends seen: the known handrail type nearest the beam length (an
  // index into DetectorConfig::handrail_types, its name and length); -1,
  // nullptr and 0 otherwise, or when the config lists no types.
  int handrail_type = -1;
  const char* handrail_type_name = nullptr;
  float length_m = 0.0f;
  // The mount surface the bar stands on: its distance from the dominant
  // plane along the normal (0 on a flat wall; a seat track or another rack
  // face on a rack wall).
  float mount_offset_m = 0.0f;
  Eigen::Vector3f p_cam_target = Eigen::Vector3f::Zero();
  Eigen::Matrix3f R_cam_target = Eigen::Matrix3f::Zero();
  std::uint32_t inliers = 0;
  StageCounts counts;
  std::int64_t processing_time_us = 0;

  Eigen::Vector3f axis() const { return R_cam_handrail.col(2); }
  Eigen::Vector3f normal() const { return R_cam_handrail.col(0); }
  int num_ends() const { return (end_seen[0] ? 1 : 0) + (end_seen[1] ? 1 : 0); }
};

}  // namespace estimator
