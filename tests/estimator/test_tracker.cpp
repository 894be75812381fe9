// The tracker's transitions (Tr1, Tr2, Tr3), its outlier gate and its
// bookkeeping, on detections made from a known world and camera motion.
#include <Eigen/Geometry>
#include <cmath>

#include "cmocka_cpp.hpp"
#include "estimator/handrail_tracker.hpp"

using namespace estimator;

namespace {

// World: a vertical handrail (axis world z) centred at the origin on a wall
// facing +x, 0.55 m long. Body from camera as on the robot's camera mount.
const Eigen::Vector3f kNormal(1, 0, 0), kAxis(0, 0, 1);

Eigen::Isometry3f body_at(float x, float y, float z) {
  Eigen::Isometry3f T = Eigen::Isometry3f::Identity();
  Eigen::Matrix3f R;
  R.col(0) = Eigen::Vector3f(-1, 0, 0);  // facing the wall
  R.col(1) = Eigen::Vector3f(0, -1, 0);
  R.col(2) = Eigen::Vector3f(0, 0, 1);
  T.linear() = R;
  T.translation() = Eigen::Vector3f(x, y, z);
  return T;
}

Eigen::Isometry3f body_from_camera() {
  Eigen::Isometry3f T = Eigen::Isometry3f::Identity();
  Eigen::Matrix3f R;
  R.col(0) = Eigen::Vector3f(0, -1, 0);
  R.col(1) = Eigen::Vector3f(0, 0, -1);
  R.col(2) = Eigen::Vector3f(1, 0, 0);
  T.linear() = R;
  T.translation() = Eigen::Vector3f(0.05f, 0.0f, 0.0f);
  return T;
}

// A detection of the bar whose visible part spans world z in [lo, hi], the
// line shifted across the wall by `shift_m` (world y).
HandrailDetection detect(const Eigen::Isometry3f& T_world_body, float lo, float hi, bool end_lo,
                         bool end_hi, float shift_m = 0.0f, bool flip_axis = false) {
  const Eigen::Isometry3f T_cam_world = (T_world_body * body_from_camera()).inverse();
  HandrailDetection d;
  d.status = DetectStatus::kFound;
  d.end_seen[0] = end_lo;
  d.end_seen[1] = end_hi;
  const int n = (end_lo ? 1 : 0) + (end_hi ? 1 : 0);
  d.state = n == 2   ? HandrailState::kBothEnds
            : n == 1 ? HandrailState::kOneEnd
                     : HandrailState::kNoEnd;
  const Eigen::Vector3f base(0.061f, shift_m, 0.0f);
  d.ends_cam[0] = T_cam_world * (base + lo * kAxis);
  d.ends_cam[1] = T_cam_world * (base + hi * kAxis);
  d.p_cam_center = T_cam_world * (base + 0.5f * (lo + hi) * kAxis);
  Eigen::Matrix3f R_world;
  R_world.col(0) = kNormal;
  R_world.col(1) = kAxis.cross(kNormal);
  R_world.col(2) = kAxis;
  if (flip_axis) {
    R_world.col(2) = -R_world.col(2);
    R_world.col(1) = -R_world.col(1);
  }
  d.R_cam_handrail = T_cam_world.rotation() * R_world;
  return d;
}

HandrailDetection nothing() {
  return HandrailDetection{};
}

void assert_center(const TrackedHandrail& t, float y, float z) {
  assert_near(t.p_world_center.x(), 0.061, 1e-4);
  assert_near(t.p_world_center.y(), y, 1e-4);
  assert_near(t.p_world_center.z(), z, 1e-4);
}

void test_transitions(void**) {
  HandrailTracker tracker;
  const Eigen::Isometry3f cam = body_from_camera();
  // Tr2: no track, one end seen: the middle of the visible part.
  const Eigen::Isometry3f near_top = body_at(0.5f, 0.0f, 0.15f);
  const TrackedHandrail& t =
      tracker.update(detect(near_top, -0.10f, 0.275f, false, true), near_top, cam);
  assert_int_equal(static_cast<int>(t.event), static_cast<int>(TrackEvent::kStarted));
  assert_center(t, 0.0f, 0.0875f);
  // Tr1: both ends: the true centre, from a camera that moved.
  const Eigen::Isometry3f far = body_at(1.0f, 0.05f, 0.0f);
  tracker.update(detect(far, -0.275f, 0.275f, true, true), far, cam);
  assert_int_equal(static_cast<int>(t.event), static_cast<int>(TrackEvent::kBothEnds));
  assert_center(t, 0.0f, 0.0f);
  // Tr3: one end, the line 1 cm across: across follows, along is kept.
  const Eigen::Isometry3f close = body_at(0.35f, 0.0f, 0.12f);
  tracker.update(detect(close, 0.05f, 0.275f, false, true, 0.01f), close, cam);
  assert_int_equal(static_cast<int>(t.event), static_cast<int>(TrackEvent::kOneEnd));
  assert_center(t, 0.01f, 0.0f);
  // No end: the same.
  tracker.update(detect(close, 0.0f, 0.2f, false, false, 0.005f), close, cam);
  assert_int_equal(static_cast<int>(t.event), static_cast<int>(TrackEvent::kNoEnd));
  assert_center(t, 0.005f, 0.0f);
  // The target stands off the wall along its normal.
  assert_near(t.p_world_target.x(), 0.061 + 0.35, 1e-4);
  assert_near((t.R_world_target.col(0) - kNormal).norm(), 0.0, 1e-5);
}

void test_outlier_gate_and_restart(void**) {
  TrackerConfig cfg;
  cfg.max_rejections = 3;
  HandrailTracker tracker(cfg);
  const Eigen::Isometry3f cam = body_from_camera(), body = body_at(0.8f, 0.0f, 0.0f);
  tracker.update(detect(body, -0.275f, 0.275f, true, true), body, cam);
  // A cable 20 cm to the side: rejected twice, the track holds.
  for (int k = 0; k < 2; ++k) {
    const TrackedHandrail& t =
        tracker.update(detect(body, -0.2f, 0.2f, false, false, 0.2f), body, cam);
    assert_int_equal(static_cast<int>(t.event), static_cast<int>(TrackEvent::kRejected));
    assert_center(t, 0.0f, 0.0f);
  }
  // A good frame in between clears the count...
  tracker.update(detect(body, -0.275f, 0.275f, true, true), body, cam);
  tracker.update(detect(body, -0.2f, 0.2f, false, false, 0.2f), body, cam);
  tracker.update(detect(body, -0.2f, 0.2f, false, false, 0.2f), body, cam);
  // ... so only the third rejection in a row restarts, at the new place.
  const TrackedHandrail& t =
      tracker.update(detect(body, -0.2f, 0.2f, false, false, 0.2f), body, cam);
  assert_int_equal(static_cast<int>(t.event), static_cast<int>(TrackEvent::kRestarted));
  assert_center(t, 0.2f, 0.0f);
}

void test_missed_frames_and_axis_sign(void**) {
  TrackerConfig cfg;
  cfg.max_missed_frames = 2;
  HandrailTracker tracker(cfg);
  const Eigen::Isometry3f cam = body_from_camera(), body = body_at(0.8f, 0.0f, 0.0f);
  assert_int_equal(static_cast<int>(tracker.update(nothing(), body, cam).event),
                   static_cast<int>(TrackEvent::kNone));
  tracker.update(detect(body, -0.275f, 0.275f, true, true), body, cam);
  const Eigen::Vector3f axis = tracker.track().R_world_handrail.col(2);
  // The detector flips its axis sign: the track keeps its own.
  tracker.update(detect(body, -0.275f, 0.275f, true, true, 0.0f, true), body, cam);
  assert_int_equal(static_cast<int>(tracker.track().event),
                   static_cast<int>(TrackEvent::kBothEnds));
  assert_near((tracker.track().R_world_handrail.col(2) - axis).norm(), 0.0, 1e-5);
  assert_near(tracker.track().R_world_handrail.determinant(), 1.0, 1e-5);
  assert_int_equal(static_cast<int>(tracker.update(nothing(), body, cam).event),
                   static_cast<int>(TrackEvent::kMissed));
  assert_true(tracker.track().valid);
  tracker.update(nothing(), body, cam);
  const TrackedHandrail& t = tracker.update(nothing(), body, cam);
  assert_int_equal(static_cast<int>(t.event), static_cast<int>(TrackEvent::kDropped));
  assert_false(t.valid);
  assert_string_equal(to_string(TrackEvent::kOneEnd), "TR3_ONE_END");
}

}  // namespace

int main() {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_transitions),
      cmocka_unit_test(test_outlier_gate_and_restart),
      cmocka_unit_test(test_missed_frames_and_axis_sign),
  };
  return cmocka_run_group_tests(tests, nullptr, nullptr);
}
