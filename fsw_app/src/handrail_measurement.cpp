#include "fsw_app/handrail_measurement.hpp"

#include <algorithm>
#include <cmath>

#include "fsw_app/msg_convert.hpp"

namespace fsw_app {

namespace loc = estimator::localization;

const char* to_string(HandrailMeasurementStatus s) {
  switch (s) {
    case HandrailMeasurementStatus::kOk:
      return "OK";
    case HandrailMeasurementStatus::kNoHandrail:
      return "NO_HANDRAIL";
    case HandrailMeasurementStatus::kNotInView:
      return "NOT_IN_VIEW";
  }
  return "UNKNOWN";
}

namespace {

bool in_view(const Eigen::Vector3d& p_cam, const HandrailFeatureModel& model) {
  return p_cam.z() > model.min_range_m &&
         std::fabs(p_cam.x()) < std::tan(model.half_fov_x_rad) * p_cam.z() &&
         std::fabs(p_cam.y()) < std::tan(model.half_fov_y_rad) * p_cam.z();
}

}  // namespace

HandrailMeasurementStatus handrail_measurement_from(const hrp::handrail_estimate_t& e,
                                                    const HandrailFeatureModel& model,
                                                    double bar_length_m,
                                                    loc::HandrailMeasurement* m) {
  m->num_features = 0;
  m->capture_time_us = e.capture_utime;
  switch (e.state) {
    case hrp::handrail_estimate_t::STATE_BE:
      m->state = estimator::HandrailState::kBothEnds;
      break;
    case hrp::handrail_estimate_t::STATE_OE:
      m->state = estimator::HandrailState::kOneEnd;
      break;
    case hrp::handrail_estimate_t::STATE_NE:
      m->state = estimator::HandrailState::kNoEnd;
      break;
    default:
      m->state = estimator::HandrailState::kNoHandrail;
      return HandrailMeasurementStatus::kNoHandrail;
  }
  if (e.deadline_missed) return HandrailMeasurementStatus::kNoHandrail;
  m->T_cam_handrail = from_msg(e.T_cam_handrail);
  const bool length_known = std::isfinite(bar_length_m) && bar_length_m > 0.0;
  if (m->state == estimator::HandrailState::kOneEnd && !length_known) {
    // The detector's OE origin is the middle of the part it sees: with the
    // along-bar component dropped that is an NE measurement.
    m->state = estimator::HandrailState::kNoEnd;
  }
  if (m->state == estimator::HandrailState::kOneEnd) {
    // The detector puts an OE frame's origin in the middle of the part it
    // sees (the paper's Tr2); the filter's model wants the bar's centre,
    // which is half a bar from the seen end toward the rest of the bar.
    if (e.num_ends < 1) return HandrailMeasurementStatus::kNoHandrail;
    const Eigen::Vector3d end(e.ends_cam_m[0][0], e.ends_cam_m[0][1], e.ends_cam_m[0][2]);
    const Eigen::Vector3d axis = m->T_cam_handrail.linear().col(2);
    const Eigen::Vector3d origin = m->T_cam_handrail.translation();
    const double inward = axis.dot(origin - end) >= 0.0 ? 1.0 : -1.0;
    const double along_end = axis.dot(end - origin);
    m->T_cam_handrail.translation() = origin + (along_end + inward * 0.5 * bar_length_m) * axis;
  }
  // Where along the bar the features go: with an end seen the origin is the
  // bar's centre and the bar spans +-L/2 (BE: the length measured in this
  // frame); with none, the origin is only somewhere on the part seen, so a
  // span about it.
  double half = model.ne_half_span_m;
  if (m->state == estimator::HandrailState::kBothEnds && e.bar_length_m > 0.0 &&
      std::isfinite(e.bar_length_m)) {
    half = 0.5 * e.bar_length_m;
  } else if (m->state != estimator::HandrailState::kNoEnd && length_known) {
    half = 0.5 * bar_length_m;
  }
  const int n = std::max(2, std::min(model.bar_points, loc::kMaxInputFeatures / 3));
  Eigen::Vector3d bar[loc::kMaxInputFeatures], wall[loc::kMaxInputFeatures];
  int n_bar = 0, n_wall = 0;
  const double wall_step_m = (model.wall_half_width_m - model.wall_min_half_width_m) /
                             (HandrailFeatureModel::kWallSteps - 1);
  for (int k = 0; k < n; ++k) {
    const double z = -half + 2.0 * half * k / (n - 1);
    const Eigen::Vector3d p_bar = m->T_cam_handrail * Eigen::Vector3d(0.0, 0.0, z);
    if (!in_view(p_bar, model)) continue;
    bar[n_bar++] = p_bar;
    // The wall either side of the bar (x = -offset in the handrail frame),
    // as far out as the camera sees it.
    for (const double side : {-1.0, 1.0}) {
      for (int step = 0; step < HandrailFeatureModel::kWallSteps; ++step) {
        const double y = side * (model.wall_half_width_m - step * wall_step_m);
        const Eigen::Vector3d p_wall =
            m->T_cam_handrail * Eigen::Vector3d(-model.wall_offset_m, y, z);
        if (in_view(p_wall, model)) {
          wall[n_wall++] = p_wall;
          break;
        }
      }
    }
  }
  if (n_bar < 2) return HandrailMeasurementStatus::kNotInView;
  loc::add_features(bar, n_bar, loc::FeatureKind::kBar, m);
  loc::add_features(wall, n_wall, loc::FeatureKind::kWall, m);
  return HandrailMeasurementStatus::kOk;
}

}  // namespace fsw_app
