#include "estimator/handrail_tracker.hpp"

#include <algorithm>
#include <cmath>

namespace estimator {
namespace {

float angle_between(const Eigen::Vector3f& a, const Eigen::Vector3f& b) {
  return std::acos(std::clamp(a.dot(b), -1.0f, 1.0f));
}

// The point of the line (through p along unit a) nearest to q.
Eigen::Vector3f nearest_on_line(const Eigen::Vector3f& p, const Eigen::Vector3f& a,
                                const Eigen::Vector3f& q) {
  return p + (q - p).dot(a) * a;
}

}  // namespace

const char* to_string(TrackEvent event) {
  switch (event) {
    case TrackEvent::kNone:
      return "NONE";
    case TrackEvent::kStarted:
      return "STARTED";
    case TrackEvent::kBothEnds:
      return "TR1_BOTH_ENDS";
    case TrackEvent::kOneEnd:
      return "TR3_ONE_END";
    case TrackEvent::kNoEnd:
      return "NO_END";
    case TrackEvent::kMissed:
      return "MISSED";
    case TrackEvent::kRejected:
      return "REJECTED";
    case TrackEvent::kRestarted:
      return "RESTARTED";
    case TrackEvent::kDropped:
      return "DROPPED";
  }
  return "UNKNOWN";
}

void HandrailTracker::reset() {
  track_ = TrackedHandrail{};
  rejections_ = 0;
  missed_ = 0;
}

void HandrailTracker::set_pose(const Eigen::Vector3f& center, const Eigen::Matrix3f& R) {
  track_.p_world_center = center;
  track_.R_world_handrail = R;
  track_.p_world_target = center + cfg_.target_standoff_m * R.col(0);
  track_.R_world_target = R;
}

void HandrailTracker::start_from(const Eigen::Vector3f& center, const Eigen::Matrix3f& R,
                                 const HandrailDetection& d, TrackEvent event) {
  track_.valid = true;
  track_.event = event;
  track_.state = d.state;
  track_.capture_time_us = d.capture_time_us;
  set_pose(center, R);
  rejections_ = 0;
  missed_ = 0;
}

const TrackedHandrail& HandrailTracker::update(const HandrailDetection& d,
                                               const Eigen::Isometry3f& T_world_body,
                                               const Eigen::Isometry3f& T_body_cam) {
  if (d.status != DetectStatus::kFound) {
    if (!track_.valid) {
      track_.event = TrackEvent::kNone;
    } else if (++missed_ > cfg_.max_missed_frames) {
      reset();
      track_.event = TrackEvent::kDropped;
    } else {
      track_.event = TrackEvent::kMissed;
    }
    return track_;
  }
  const Eigen::Isometry3f T_world_cam = T_world_body * T_body_cam;
  const Eigen::Matrix3f R_wc = T_world_cam.rotation();
  Eigen::Matrix3f R = R_wc * d.R_cam_handrail;
  // Keep the axis pointing the way the track's does (the detector fixes
  // its sign in the image, which can flip as the camera moves).
  if (track_.valid && R.col(2).dot(track_.R_world_handrail.col(2)) < 0.0f) {
    R.col(2) = -R.col(2);
    R.col(1) = -R.col(1);
  }
  const Eigen::Vector3f axis = R.col(2);
  const Eigen::Vector3f visible_middle = T_world_cam * d.p_cam_center;

  if (!track_.valid) {
    // Tr1 or Tr2: the detector's centre is midway between the ends when
    // both are seen, the middle of the visible bar otherwise.
    start_from(visible_middle, R, d, TrackEvent::kStarted);
    return track_;
  }

  // The candidate centre under this frame's transition.
  Eigen::Vector3f center;
  TrackEvent event;
  if (d.state == HandrailState::kBothEnds) {
    center = visible_middle;  // Tr1
    event = TrackEvent::kBothEnds;
  } else if (d.state == HandrailState::kOneEnd) {
    // Tr3: across from the new line (through the seen end), along kept.
    const int e = d.end_seen[0] ? 0 : 1;
    center = nearest_on_line(T_world_cam * d.ends_cam[e], axis, track_.p_world_center);
    event = TrackEvent::kOneEnd;
  } else {
    center = nearest_on_line(visible_middle, axis, track_.p_world_center);
    event = TrackEvent::kNoEnd;
  }

  // Outlier gate: a jump of the centre (across the bar, or anywhere when
  // both ends fix it) or a turn of the axis or the normal.
  const Eigen::Vector3f jump = center - track_.p_world_center;
  const Eigen::Vector3f old_axis = track_.R_world_handrail.col(2);
  const float jump_m =
      event == TrackEvent::kBothEnds ? jump.norm() : (jump - jump.dot(old_axis) * old_axis).norm();
  const bool outlier =
      jump_m > cfg_.gate_position_m || angle_between(axis, old_axis) > cfg_.gate_angle_rad ||
      angle_between(R.col(0), track_.R_world_handrail.col(0)) > cfg_.gate_angle_rad;
  if (outlier) {
    if (++rejections_ >= cfg_.max_rejections) {
      // The world moved (or the track was wrong): start again cleanly.
      start_from(visible_middle, R, d, TrackEvent::kRestarted);
    } else {
      track_.event = TrackEvent::kRejected;
    }
    return track_;
  }
  rejections_ = 0;
  missed_ = 0;
  track_.event = event;
  track_.state = d.state;
  track_.capture_time_us = d.capture_time_us;
  set_pose(center, R);
  return track_;
}

}  // namespace estimator
