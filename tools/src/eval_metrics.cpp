#include "eval_metrics.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "estimator/handrail_pose.hpp"

namespace tools {
namespace {
constexpr double kRadToDeg = 180.0 / M_PI;
}

int target_handrail(const sim_hal::FrameTruth& truth, double gripper_angle_rad) {
  int best = -1;
  double best_diff = 0.0;
  for (std::size_t k = 0; k < truth.handrails.size(); ++k) {
    const sim_hal::HandrailTruth& h = truth.handrails[k];
    if (h.visible_fraction < 0.3) continue;
    const double psi = std::atan2(std::fabs(h.axis_cam.x()), std::fabs(h.axis_cam.y()));
    const double diff = std::fabs(psi - gripper_angle_rad);
    if (best < 0 || diff < best_diff) {
      best = static_cast<int>(k);
      best_diff = diff;
    }
  }
  return best;
}

int target_handrail_in_reach(const sim_hal::FrameTruth& truth, double gripper_angle_rad) {
  int best = -1;
  double best_diff = 0.0;
  for (std::size_t k = 0; k < truth.handrails.size(); ++k) {
    const sim_hal::HandrailTruth& h = truth.handrails[k];
    const double range_m = h.visible_center_cam.norm();
    if (h.visible_fraction < 0.35 || range_m < 0.25 || range_m > kReachMaxM) continue;
    const double psi = std::atan2(std::fabs(h.axis_cam.x()), std::fabs(h.axis_cam.y()));
    const double diff = std::fabs(psi - gripper_angle_rad);
    if (best < 0 || diff < best_diff) {
      best = static_cast<int>(k);
      best_diff = diff;
    }
  }
  return best;
}

int scored_target(const estimator::HandrailDetection& d, const sim_hal::FrameTruth& truth,
                  double gripper_angle_rad, int target, bool in_reach) {
  if (target < 0 || d.status != estimator::DetectStatus::kFound) return target;
  const auto angle_off = [&](const sim_hal::HandrailTruth& h) {
    return std::fabs(std::atan2(std::fabs(h.axis_cam.x()), std::fabs(h.axis_cam.y())) -
                     gripper_angle_rad);
  };
  // Parallel handrails tie with the target (within a degree).
  const double window_rad = std::max(
      M_PI / 4.0, angle_off(truth.handrails[static_cast<std::size_t>(target)]) + M_PI / 180.0);
  int best = -1;
  double best_mm = 0.0;
  for (std::size_t k = 0; k < truth.handrails.size(); ++k) {
    const sim_hal::HandrailTruth& h = truth.handrails[k];
    if (angle_off(h) > window_rad) continue;
    if (in_reach && h.visible_center_cam.norm() > kReachMaxM) continue;
    const FrameErrors e = score_detection(d, h);
    if (is_correct(e) && (best < 0 || e.perpendicular_mm < best_mm)) {
      best = static_cast<int>(k);
      best_mm = e.perpendicular_mm;
    }
  }
  return best >= 0 ? best : target;
}

FrameErrors score_detection(const estimator::HandrailDetection& d,
                            const sim_hal::HandrailTruth& t) {
  const Eigen::Matrix3f R_gt =
      estimator::handrail_frame(t.normal_cam.cast<float>(), t.axis_cam.cast<float>());
  const Eigen::Vector3f e = R_gt.transpose() * (d.p_cam_center - t.center_cam.cast<float>());
  FrameErrors out{};
  out.x_mm = 1000.0 * e.x();
  out.y_mm = 1000.0 * e.y();
  out.z_mm = 1000.0 * e.z();
  out.perpendicular_mm = std::hypot(out.x_mm, out.y_mm);
  const Eigen::AngleAxisf err(R_gt.transpose() * d.R_cam_handrail);
  const Eigen::Vector3f rotvec = err.axis() * err.angle();
  out.roll_deg = kRadToDeg * rotvec.x();
  out.pitch_deg = kRadToDeg * rotvec.y();
  out.yaw_deg = kRadToDeg * rotvec.z();
  out.axis_deg = kRadToDeg * std::acos(std::min(1.0f, std::fabs(R_gt.col(2).dot(d.axis()))));
  out.normal_deg = kRadToDeg * std::acos(std::clamp(R_gt.col(0).dot(d.normal()), -1.0f, 1.0f));
  out.beam_mm = d.state == estimator::HandrailState::kBothEnds
                    ? 1000.0 * (d.beam_length_m - t.length_m)
                    : NAN;
  return out;
}

bool is_correct(const FrameErrors& e) {
  return e.perpendicular_mm < 50.0 && e.axis_deg < 15.0;
}

estimator::HandrailState expected_state(const sim_hal::HandrailTruth& t) {
  const int n = (t.end_in_view[0] ? 1 : 0) + (t.end_in_view[1] ? 1 : 0);
  return n == 2   ? estimator::HandrailState::kBothEnds
         : n == 1 ? estimator::HandrailState::kOneEnd
                  : estimator::HandrailState::kNoEnd;
}

double Stats::mean() const {
  if (values.empty()) return NAN;
  double s = 0.0;
  for (double v : values) s += v;
  return s / static_cast<double>(values.size());
}

double Stats::stddev() const {
  if (values.size() < 2) return 0.0;
  const double m = mean();
  double s = 0.0;
  for (double v : values) s += (v - m) * (v - m);
  return std::sqrt(s / static_cast<double>(values.size() - 1));
}

double Stats::median() const {
  if (values.empty()) return NAN;
  std::vector<double> v = values;
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2), v.end());
  return v[v.size() / 2];
}

double Stats::percentile(double p) const {
  if (values.empty()) return NAN;
  std::vector<double> v = values;
  const double rank = std::ceil(std::fmin(std::fmax(p, 0.0), 100.0) / 100.0 * v.size());
  const std::size_t k = rank < 1.0 ? 0 : static_cast<std::size_t>(rank) - 1;
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(k), v.end());
  return v[k];
}

std::string Stats::mean_sd(int decimals) const {
  if (values.empty()) return "-";
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f ± %.*f", decimals, mean(), decimals, stddev());
  return buf;
}

namespace {

ConfusionColumn said(estimator::HandrailState state) {
  switch (state) {
    case estimator::HandrailState::kBothEnds:
      return kSaidBE;
    case estimator::HandrailState::kOneEnd:
      return kSaidOE;
    case estimator::HandrailState::kNoEnd:
      return kSaidNE;
    case estimator::HandrailState::kNoHandrail:
      break;
  }
  return kSaidNH;
}

ConfusionRow truth_row(estimator::HandrailState state) {
  switch (state) {
    case estimator::HandrailState::kBothEnds:
      return kTruthBE;
    case estimator::HandrailState::kOneEnd:
      return kTruthOE;
    case estimator::HandrailState::kNoEnd:
      return kTruthNE;
    case estimator::HandrailState::kNoHandrail:
      break;
  }
  return kTruthNH;
}

}  // namespace

void Tally::add(const estimator::HandrailDetection& d, const sim_hal::FrameTruth& truth, int target,
                int reach_target) {
  ++frames;
  time_ms.add(d.processing_time_us / 1000.0);
  const bool has_target = target >= 0;
  target_frames += has_target;
  reach_target_frames += reach_target >= 0;
  const int row = has_target
                      ? truth_row(expected_state(truth.handrails[static_cast<std::size_t>(target)]))
                      : kTruthNH;
  if (reach_target >= 0 && d.status == estimator::DetectStatus::kFound) {
    reach_correct +=
        is_correct(score_detection(d, truth.handrails[static_cast<std::size_t>(reach_target)]));
  }
  if (d.status != estimator::DetectStatus::kFound) {
    std::string why = estimator::to_string(d.status);
    if (d.status == estimator::DetectStatus::kNoLine) {
      why += std::string(" (") + estimator::to_string(d.counts.first_rejection) + ")";
    }
    ++reasons[why];
    ++confusion[row][kSaidNH];
    if (has_target) missed_frames.push_back(truth.frame);
    return;
  }
  ++found;
  if (!has_target) {
    // Too little of any handrail in view to expect a detection; one that
    // matches a handrail in view is no error, anything else is false.
    bool matches_any = false;
    for (const sim_hal::HandrailTruth& h : truth.handrails)
      matches_any |= is_correct(score_detection(d, h));
    false_found += !matches_any;
    ++reasons[matches_any ? "FOUND" : "FALSE"];
    ++confusion[row][matches_any ? said(d.state) : kSaidFalse];
    if (!matches_any) false_frames.push_back(truth.frame);
    return;
  }
  const sim_hal::HandrailTruth& t = truth.handrails[static_cast<std::size_t>(target)];
  const FrameErrors e = score_detection(d, t);
  if (!is_correct(e)) {
    ++false_found;
    ++reasons["FALSE"];
    ++confusion[row][kSaidFalse];
    missed_frames.push_back(truth.frame);
    false_frames.push_back(truth.frame);
  } else {
    ++correct;
    ++state_checked;
    state_right += d.state == expected_state(t);
    correct_perpendicular.add(e.perpendicular_mm);
    correct_axis.add(e.axis_deg);
    ++reasons["FOUND"];
    ++confusion[row][said(d.state)];
  }
  // Errors over every detection of a frame that has a target, as the
  // paper's Figure 15 does: picking a cable shows up as a large error.
  x.add(e.x_mm);
  y.add(e.y_mm);
  if (d.state == estimator::HandrailState::kBothEnds) z.add(e.z_mm);
  perpendicular.add(e.perpendicular_mm);
  roll.add(e.roll_deg);
  pitch.add(e.pitch_deg);
  yaw.add(e.yaw_deg);
  axis.add(e.axis_deg);
  normal.add(e.normal_deg);
  if (!std::isnan(e.beam_mm)) beam.add(e.beam_mm);
}

void Tally::merge(const Tally& o) {
  frames += o.frames;
  target_frames += o.target_frames;
  found += o.found;
  correct += o.correct;
  false_found += o.false_found;
  state_checked += o.state_checked;
  state_right += o.state_right;
  reach_target_frames += o.reach_target_frames;
  reach_correct += o.reach_correct;
  Stats Tally::*const all[] = {
      &Tally::x,           &Tally::y,     &Tally::z,       &Tally::perpendicular,
      &Tally::roll,        &Tally::pitch, &Tally::yaw,     &Tally::axis,
      &Tally::normal,      &Tally::beam,  &Tally::time_ms, &Tally::correct_perpendicular,
      &Tally::correct_axis};
  for (Stats Tally::*st : all) {
    (this->*st).values.insert((this->*st).values.end(), (o.*st).values.begin(),
                              (o.*st).values.end());
  }
  for (const auto& kv : o.reasons) reasons[kv.first] += kv.second;
  missed_frames.insert(missed_frames.end(), o.missed_frames.begin(), o.missed_frames.end());
  false_frames.insert(false_frames.end(), o.false_frames.begin(), o.false_frames.end());
  for (int r = 0; r < kConfusionRows; ++r)
    for (int c = 0; c < kConfusionColumns; ++c) confusion[r][c] += o.confusion[r][c];
}

std::string frame_ranges(const std::vector<std::uint64_t>& frames, std::size_t max_ranges) {
  if (frames.empty()) return "none";
  std::string out = std::to_string(frames.size()) + ": ";
  std::size_t ranges = 0, k = 0;
  for (; k < frames.size() && ranges < max_ranges; ++ranges) {
    std::size_t j = k;
    while (j + 1 < frames.size() && frames[j + 1] == frames[j] + 1) ++j;
    if (ranges) out += ", ";
    out += std::to_string(frames[k]);
    if (j > k) out += "-" + std::to_string(frames[j]);
    k = j + 1;
  }
  if (k < frames.size()) out += ", ... (" + std::to_string(frames.size() - k) + " more)";
  return out;
}

}  // namespace tools
