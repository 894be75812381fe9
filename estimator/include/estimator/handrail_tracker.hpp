#pragma once
// Keeps the handrail's centre in the world frame over frames, with the
// paper's transitions between handrail states (Figure 10):
//   Tr1  both ends seen: the centre is midway between them;
//   Tr2  no track yet, one or no end seen: the middle of the visible bar;
//   Tr3  a track, one end seen: the position across the bar comes from the
//        new line through that end, the position along the bar is kept.
// With a track and no end seen, the line also updates the position across
// the bar and keeps the one along it (the paper keeps both; the line's
// lateral position is a good measurement, so we use it).
// An outlier gate rejects a detection that jumps from the track; after
// max_rejections in a row the track restarts from the detection.
// No allocation, no exceptions.
#include <Eigen/Geometry>
#include <cstdint>

#include "estimator/types.hpp"

namespace estimator {

struct TrackerConfig {
  float gate_position_m = 0.10f;     // jump of the centre (across the bar unless both ends seen)
  float gate_angle_rad = 0.1745f;    // 10 deg of the axis or the normal
  std::uint32_t max_rejections = 5;  // then restart from the detection
  std::uint32_t max_missed_frames = 25;  // frames without a detection before the track is dropped
  float target_standoff_m = 0.35f;       // as DetectorConfig::target_standoff_m
};

enum class TrackEvent : std::uint8_t {
  kNone,       // no track and nothing detected
  kStarted,    // Tr1 or Tr2 from no track
  kBothEnds,   // Tr1
  kOneEnd,     // Tr3
  kNoEnd,      // line only: across updated, along kept
  kMissed,     // nothing detected this frame; the track holds
  kRejected,   // the detection failed the outlier gate; the track holds
  kRestarted,  // too many rejections: restarted from the detection
  kDropped,    // too many missed frames: no track
};
const char* to_string(TrackEvent event);

struct TrackedHandrail {
  bool valid = false;
  TrackEvent event = TrackEvent::kNone;
  HandrailState state = HandrailState::kNoHandrail;  // of the last accepted detection
  std::int64_t capture_time_us = 0;                  // of the last accepted detection
  Eigen::Vector3f p_world_center = Eigen::Vector3f::Zero();
  Eigen::Matrix3f R_world_handrail = Eigen::Matrix3f::Identity();  // columns: normal, y, axis
  Eigen::Vector3f p_world_target = Eigen::Vector3f::Zero();
  Eigen::Matrix3f R_world_target = Eigen::Matrix3f::Identity();
};

class HandrailTracker {
 public:
  explicit HandrailTracker(const TrackerConfig& cfg = TrackerConfig{}) : cfg_(cfg) {}

  // One frame: the detection and where the camera was (world from body at
  // capture time, body from camera).
  const TrackedHandrail& update(const HandrailDetection& detection,
                                const Eigen::Isometry3f& T_world_body,
                                const Eigen::Isometry3f& T_body_cam);
  const TrackedHandrail& track() const { return track_; }
  void reset();

 private:
  void start_from(const Eigen::Vector3f& center, const Eigen::Matrix3f& R,
                  const HandrailDetection& d, TrackEvent event);
  void set_pose(const Eigen::Vector3f& center, const Eigen::Matrix3f& R);

  TrackerConfig cfg_;
  TrackedHandrail track_;
  std::uint32_t rejections_ = 0;
  std::uint32_t missed_ = 0;
};

}  // namespace estimator
