#include "fsw_app/input_checks.hpp"

#include <cmath>

namespace fsw_app {

const char* to_string(InputReject reason) {
  switch (reason) {
    case InputReject::kUndecodable:
      return "UNDECODABLE";
    case InputReject::kTrailingBytes:
      return "TRAILING_BYTES";
    case InputReject::kNotFinite:
      return "NOT_FINITE";
    case InputReject::kOutOfRange:
      return "OUT_OF_RANGE";
    case InputReject::kStale:
      return "STALE";
    case InputReject::kBadLength:
      return "BAD_LENGTH";
    case InputReject::kDecoderFault:
      return "DECODER_FAULT";
    case InputReject::kFuture:
      return "FUTURE";
    case InputReject::kSequence:
      return "SEQUENCE";
    case InputReject::kRateLimited:
      return "RATE_LIMITED";
    case InputReject::kWrongSource:
      return "WRONG_SOURCE";
  }
  return "UNKNOWN";
}

namespace {

// Collects the verdict over a message's fields: the first failure wins, a
// non-finite number before a range.
class Verdict {
 public:
  explicit Verdict(InputReject* why) : why_(why) {}
  bool ok() const { return ok_; }

  void finite(const double* v, int n) {
    for (int k = 0; k < n; ++k) {
      if (!std::isfinite(v[k])) fail(InputReject::kNotFinite);
    }
  }
  void finite(double v) { finite(&v, 1); }
  // A vector's length at most `max` (finite checked first).
  void norm_at_most(const double* v, int n, double max) {
    finite(v, n);
    double s = 0.0;
    for (int k = 0; k < n; ++k) s += v[k] * v[k];
    if (ok_ && std::sqrt(s) > max) fail(InputReject::kOutOfRange);
  }
  void within(double v, double lo, double hi) {
    finite(v);
    if (ok_ && !(v >= lo && v <= hi)) fail(InputReject::kOutOfRange);
  }
  void count_within(std::int64_t v, std::int64_t lo, std::int64_t hi) {
    if (v < lo || v > hi) fail(InputReject::kOutOfRange);
  }
  void equals(std::int64_t v, std::int64_t expected, InputReject otherwise) {
    if (v != expected) fail(otherwise);
  }
  void pose(const hrp::pose_t& p, double max_position_m) {
    norm_at_most(p.position_m, 3, max_position_m);
    finite(p.quat_wxyz, 4);
    double s = 0.0;
    for (double q : p.quat_wxyz) s += q * q;
    if (ok_ && std::fabs(std::sqrt(s) - 1.0) > kUnitQuaternionTolerance) {
      fail(InputReject::kOutOfRange);
    }
  }

 private:
  void fail(InputReject reason) {
    if (ok_) *why_ = reason;
    ok_ = false;
  }
  InputReject* why_;
  bool ok_ = true;
};

constexpr std::int64_t kMaxCount = std::int64_t{1} << 48;

}  // namespace

bool check_message(const hrp::robot_pose_t& m, InputReject* why) {
  Verdict v(why);
  v.count_within(m.utime, 0, INT64_MAX);
  v.pose(m.T_world_body, kMaxWorldPosition_m);
  v.norm_at_most(m.velocity_mps, 3, kMaxSpeed_mps);
  v.norm_at_most(m.angular_velocity_rps, 3, kMaxAngularSpeed_rps);
  for (const auto& row : m.pose_covariance) v.finite(row, 6);
  // A variance is never negative; 1e6 (a kilometre, 1000 rad) is no estimate.
  for (int k = 0; k < 6; ++k) v.within(m.pose_covariance[k][k], 0.0, 1e6);
  // The robot's tasks fly on the filter's pose only: the truth, the GP's
  // fix or a stray sender on ROBOT_POSE would replace it in every task's
  // mailbox (and, repeated, hold the robot still) if it were taken in.
  v.equals(m.source, hrp::robot_pose_t::SOURCE_FILTER, InputReject::kWrongSource);
  return v.ok();
}

bool check_message(const hrp::imu_sample_t& m, InputReject* why) {
  Verdict v(why);
  v.count_within(m.utime, 0, INT64_MAX);
  v.count_within(m.seq, 0, INT64_MAX);
  v.finite(m.omega_body_radps, 3);
  v.finite(m.a_body_mps2, 3);
  return v.ok();
}

bool check_message(const hrp::gp_pose_t& m, InputReject* why) {
  Verdict v(why);
  v.count_within(m.utime, 0, INT64_MAX);
  v.count_within(m.capture_utime, 0, INT64_MAX);
  v.count_within(m.seq, 0, INT64_MAX);
  v.pose(m.T_world_body, kMaxWorldPosition_m);
  for (const auto& row : m.covariance) v.finite(row, 6);
  return v.ok();
}

// The command and its angles are judged by the arm's own rules (with a
// reason in ARM_STATE); here only what those rules cannot see: numbers
// that are not numbers.
bool check_message(const hrp::perch_command_t& m, InputReject* why) {
  Verdict v(why);
  v.finite(m.tilt_rad);
  v.finite(m.pan_rad);
  return v.ok();
}

bool check_message(const hrp::handrail_estimate_t& m, InputReject* why) {
  Verdict v(why);
  v.count_within(m.state, hrp::handrail_estimate_t::STATE_NH, hrp::handrail_estimate_t::STATE_NE);
  v.count_within(m.num_ends, 0, 2);
  v.count_within(m.frame_id, 0, INT64_MAX);
  // A handrail in view is within a few metres; the world poses within the
  // station.
  constexpr double kMaxInView_m = 20.0;
  if (m.state != hrp::handrail_estimate_t::STATE_NH) {
    v.pose(m.T_cam_handrail, kMaxInView_m);
    v.pose(m.T_body_handrail, kMaxInView_m);
    v.pose(m.T_body_target, kMaxInView_m);
    for (const auto& end : m.ends_cam_m) v.norm_at_most(end, 3, kMaxInView_m);
    v.within(m.bar_length_m, 0.0, 10.0);
  }
  if (m.target_in_world) {
    v.pose(m.T_world_target, kMaxWorldPosition_m);
    v.pose(m.T_world_handrail, kMaxWorldPosition_m);
  }
  return v.ok();
}

bool check_message(const hrp::arm_state_t& m, InputReject* why) {
  Verdict v(why);
  v.count_within(m.state, hrp::arm_state_t::INIT, hrp::arm_state_t::FAULT);
  v.finite(m.tilt_rad);
  v.finite(m.pan_rad);
  v.finite(m.tilt_goal_rad);
  v.finite(m.pan_goal_rad);
  return v.ok();
}

bool check_message(const hrp::approach_status_t& m, InputReject* why) {
  Verdict v(why);
  v.within(m.position_error_m, 0.0, 2.0 * kMaxWorldPosition_m);
  v.within(m.angle_error_rad, 0.0, 4.0);
  v.count_within(m.camera, hrp::approach_status_t::CAMERA_STREAMING,
                 hrp::approach_status_t::CAMERA_NOT_SEEN);
  return v.ok();
}

bool check_message(const hrp::body_velocity_command_t& m, InputReject* why) {
  Verdict v(why);
  v.norm_at_most(m.velocity_mps, 3, kMaxSpeed_mps);
  v.norm_at_most(m.angular_velocity_rps, 3, kMaxAngularSpeed_rps);
  return v.ok();
}

bool check_message(const hrp::estimator_health_t& m, InputReject* why) {
  Verdict v(why);
  v.count_within(m.frames_received, 0, kMaxCount);
  v.count_within(m.frames_processed, 0, kMaxCount);
  v.count_within(m.frames_dropped, 0, kMaxCount);
  v.count_within(m.frames_corrupt, 0, kMaxCount);
  v.count_within(m.deadline_misses, 0, kMaxCount);
  return v.ok();
}

bool check_message(const hrp::input_health_t& m, InputReject* why) {
  Verdict v(why);
  v.count_within(m.num_reasons, 0, hrp::input_health_t::MAX_REASONS);
  for (std::int64_t n : m.accepted) v.count_within(n, 0, INT64_MAX);
  for (const auto& row : m.rejected) {
    for (std::int64_t n : row) v.count_within(n, 0, INT64_MAX);
  }
  return v.ok();
}

bool check_message(const hrp::localization_health_t& m, InputReject* why) {
  Verdict v(why);
  v.count_within(m.imu_seq_gaps, 0, INT64_MAX);
  v.count_within(m.features_gated, 0, INT64_MAX);
  v.count_within(m.handrail_unusable, 0, INT64_MAX);
  v.within(m.position_sigma_m, 0.0, 1e6);
  v.within(m.attitude_sigma_rad, 0.0, 1e6);
  return v.ok();
}

}  // namespace fsw_app
