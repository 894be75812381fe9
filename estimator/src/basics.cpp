// Small shared pieces: validity, configuration presets, enum strings, the
// workspace's allocation.
#include <cmath>

#include "estimator/config.hpp"
#include "estimator/organized_cloud.hpp"
#include "estimator/types.hpp"
#include "estimator/workspace.hpp"

namespace estimator {

HandrailGeometry paper_round_handrail(float bar_length_m) {
  // Legs l_H = 6.5 cm, bar b_D = 3.5 cm: centre line at l_H + b_D / 2.
  return {0.035f, 0.035f, 0.065f + 0.0175f, bar_length_m};
}

HandrailGeometry iss_handrail(float bar_length_m) {
  return {0.019f, 0.035f, 0.061f, bar_length_m, 0.055f, 0.102f};
}

namespace {
float offset_min_m(const HandrailGeometry& h) {
  return h.bar_center_offset_min_m > 0.0f ? h.bar_center_offset_min_m : h.bar_center_offset_m;
}
float offset_max_m(const HandrailGeometry& h) {
  return h.bar_center_offset_max_m > 0.0f ? h.bar_center_offset_max_m : h.bar_center_offset_m;
}
}  // namespace

float bar_front_min_m(const HandrailGeometry& h) {
  return offset_min_m(h) + 0.5f * h.bar_depth_m;
}
float bar_front_max_m(const HandrailGeometry& h) {
  return offset_max_m(h) + 0.5f * h.bar_depth_m;
}

float gap_min_m(const DetectorConfig& cfg) {
  return cfg.handrail.bar_center_offset_m - 0.5f * cfg.handrail.bar_depth_m - cfg.gap_margin_m;
}
float gap_max_m(const DetectorConfig& cfg) {
  return cfg.handrail.bar_center_offset_m + 0.5f * cfg.handrail.bar_depth_m + cfg.gap_margin_m;
}
float cross_distance_m(const DetectorConfig& cfg) {
  const float b_d = std::fmax(cfg.handrail.bar_width_m, cfg.handrail.bar_depth_m);
  return std::sqrt(2.0f) * b_d + cfg.cross_delta_m;
}

const char* validate(const DetectorConfig& c) {
  const HandrailGeometry& h = c.handrail;
  if (!(h.bar_width_m > 0.005f && h.bar_width_m < 0.2f)) return "handrail.bar_width_m";
  if (!(h.bar_depth_m > 0.005f && h.bar_depth_m < 0.2f)) return "handrail.bar_depth_m";
  if (!(h.bar_center_offset_m > 0.5f * h.bar_depth_m && h.bar_center_offset_m < 0.5f))
    return "handrail.bar_center_offset_m";
  if (!(h.bar_length_m > 0.05f && h.bar_length_m < 3.0f)) return "handrail.bar_length_m";
  if (!(offset_min_m(h) > 0.5f * h.bar_depth_m && offset_min_m(h) <= h.bar_center_offset_m))
    return "handrail.bar_center_offset_min_m";
  if (!(offset_max_m(h) >= h.bar_center_offset_m && offset_max_m(h) < 0.5f))
    return "handrail.bar_center_offset_max_m";
  if (!(c.min_range_m > 0.0f && c.max_range_m > c.min_range_m)) return "max_range_m";
  if (!(c.max_find_range_m > c.min_range_m && c.max_find_range_m <= c.max_range_m)) {
    return "max_find_range_m";
  }
  if (c.plane_iterations == 0 || c.plane_iterations > 10000) return "plane_iterations";
  if (c.plane_max_iterations < c.plane_iterations || c.plane_max_iterations > 10000) {
    return "plane_max_iterations";
  }
  if (c.plane_score_samples < 50 || c.plane_score_samples > Workspace::kMaxScoreSamples) {
    return "plane_score_samples";
  }
  if (!(c.plane_inlier_m > 0.0f)) return "plane_inlier_m";
  if (!(c.plane_min_inlier_fraction > 0.0f && c.plane_min_inlier_fraction < 1.0f))
    return "plane_min_inlier_fraction";
  if (!(c.gap_margin_m >= 0.0f)) return "gap_margin_m";
  if (gap_min_m(c) <= c.wall_tolerance_m) return "wall_tolerance_m";
  if (!(c.side_width_min_ratio > 0.0f && c.side_width_max_ratio > c.side_width_min_ratio))
    return "side_width_max_ratio";
  if (!(c.run_peak_tolerance_m > 0.0f)) return "run_peak_tolerance_m";
  if (c.line_iterations == 0 || c.line_iterations > 10000) return "line_iterations";
  if (c.line_score_samples < 50 || c.line_score_samples > Workspace::kMaxScoreSamples) {
    return "line_score_samples";
  }
  if (!(c.line_inlier_m > 0.0f)) return "line_inlier_m";
  if (c.line_attempts == 0 || c.line_attempts > 32) return "line_attempts";
  if (!(c.cluster_gap_m > 0.0f)) return "cluster_gap_m";
  if (!(c.beam_length_min_ratio > 0.0f && c.beam_length_max_ratio > c.beam_length_min_ratio))
    return "beam_length_max_ratio";
  if (!(c.end_search_m > 0.0f)) return "end_search_m";
  if (!(c.min_visible_length_m > 0.0f)) return "min_visible_length_m";
  if (!(c.min_visible_fraction > 0.0f && c.min_visible_fraction <= 1.0f)) {
    return "min_visible_fraction";
  }
  if (!(c.end_drop_max_m > 0.0f)) return "end_drop_max_m";
  if (!(c.front_height_tolerance_m > 0.0f)) return "front_height_tolerance_m";
  if (!(c.own_surface_min_tilt_deg > 0.0f && c.own_surface_min_tilt_deg <= 90.0f)) {
    return "own_surface_min_tilt_deg";
  }
  if (c.mount_accept_inliers == 0) return "mount_accept_inliers";
  if (c.max_width == 0 || c.max_height == 0 || c.max_width > Workspace::kMaxWidth ||
      c.max_height > 4096)
    return "max_width";
  if (c.budget_us < 0) return "budget_us";
  if (!(c.mount_search_m >= 0.0f && c.mount_search_m <= 0.3f)) return "mount_search_m";
  // The histogram (kMountHistogramBins) spans at most 0.64 m.
  if (!(c.mount_bay_max_m >= c.mount_bay_min_m && c.mount_bay_max_m <= 0.45f)) {
    return "mount_bay_max_m";
  }
  if (!(c.mount_bay_min_m >= 0.0f)) return "mount_bay_min_m";
  if (!(c.mount_step_m >= 0.0f && c.mount_step_m <= 0.1f)) return "mount_step_m";
  if (!(c.mount_min_fraction > 0.0f && c.mount_min_fraction < 1.0f)) return "mount_min_fraction";
  if (!(c.mount_beside_min_m >= 0.0f && c.mount_beside_max_m > c.mount_beside_min_m &&
        c.mount_beside_max_m <= 0.3f)) {
    return "mount_beside_max_m";
  }
  if (!(c.mount_beside_tolerance_m > 0.0f)) return "mount_beside_tolerance_m";
  if (!(c.mount_beside_min_fraction >= 0.0f && c.mount_beside_min_fraction <= 1.0f)) {
    return "mount_beside_min_fraction";
  }
  if (c.max_mount_hypotheses == 0 || c.max_mount_hypotheses > kMaxMountHypotheses) {
    return "max_mount_hypotheses";
  }
  if (c.max_mount_hypotheses_bay < c.max_mount_hypotheses ||
      c.max_mount_hypotheses_bay > kMaxMountHypotheses) {
    return "max_mount_hypotheses_bay";
  }
  if (c.front_peak_mounts > kMaxMountHypotheses - c.max_mount_hypotheses_bay) {
    return "front_peak_mounts";
  }
  if (!(c.line_max_turn_deg > 0.0f && c.line_max_turn_deg <= 90.0f)) return "line_max_turn_deg";
  if (!(c.profile_min_obliquity_deg >= 0.0f && c.profile_min_obliquity_deg <= 90.0f)) {
    return "profile_min_obliquity_deg";
  }
  if (!(c.profile_min_spread_m >= 0.0f && c.profile_min_spread_m < 0.2f)) {
    return "profile_min_spread_m";
  }
  if (!(c.clearance_low_m > 0.0f && c.clearance_low_m < c.clearance_high_m)) {
    return "clearance_low_m";
  }
  if (!(c.clearance_high_m <= gap_min_m(c))) return "clearance_high_m";
  if (!(c.clearance_max_solid_fraction > 0.0f && c.clearance_max_solid_fraction <= 1.0f)) {
    return "clearance_max_solid_fraction";
  }
  if (c.handrail_type_count > kMaxHandrailTypes) return "handrail_types";
  for (std::uint32_t k = 0; k < c.handrail_type_count; ++k) {
    const float length = c.handrail_types[k].bar_length_m;
    if (!(length > 0.05f && length < 3.0f) || c.handrail_types[k].name == nullptr) {
      return "handrail_types";
    }
  }
  return nullptr;
}

const char* to_string(HandrailState state) {
  switch (state) {
    case HandrailState::kNoHandrail:
      return "NH";
    case HandrailState::kBothEnds:
      return "BE";
    case HandrailState::kOneEnd:
      return "OE";
    case HandrailState::kNoEnd:
      return "NE";
  }
  return "??";
}

const char* to_string(LineVerdict verdict) {
  switch (verdict) {
    case LineVerdict::kAccepted:
      return "ACCEPTED";
    case LineVerdict::kTooFewPoints:
      return "TOO_FEW_POINTS";
    case LineVerdict::kWrongHeight:
      return "WRONG_HEIGHT";
    case LineVerdict::kNoCenterLine:
      return "NO_CENTER_LINE";
    case LineVerdict::kTooShort:
      return "TOO_SHORT";
    case LineVerdict::kTooLong:
      return "TOO_LONG";
    case LineVerdict::kNoMountBeside:
      return "NO_MOUNT_BESIDE";
    case LineVerdict::kRampEnd:
      return "RAMP_END";
    case LineVerdict::kShallowProfile:
      return "SHALLOW_PROFILE";
    case LineVerdict::kSolidBelow:
      return "SOLID_BELOW";
    case LineVerdict::kTooFar:
      return "TOO_FAR";
    case LineVerdict::kNotOnTrack:
      return "NOT_ON_TRACK";
    case LineVerdict::kNoTrackPastEnd:
      return "NO_TRACK_PAST_END";
    case LineVerdict::kCrossesBar:
      return "CROSSES_BAR";
    case LineVerdict::kBeamLength:
      return "BEAM_LENGTH";
  }
  return "UNKNOWN";
}

const char* to_string(DetectStatus status) {
  switch (status) {
    case DetectStatus::kFound:
      return "FOUND";
    case DetectStatus::kEmptyFrame:
      return "EMPTY_FRAME";
    case DetectStatus::kFrameTooLarge:
      return "FRAME_TOO_LARGE";
    case DetectStatus::kNoPlane:
      return "NO_PLANE";
    case DetectStatus::kNoCandidates:
      return "NO_CANDIDATES";
    case DetectStatus::kNoLine:
      return "NO_LINE";
    case DetectStatus::kDeadlineMissed:
      return "DEADLINE_MISSED";
  }
  return "UNKNOWN";
}

Workspace::Workspace(std::size_t n)
    : max_pixels(n),
      signed_distance_m(new float[n]),
      plane_distance_m(new float[n]),
      local_distance_m(new float[n]),
      gap_widen_m(new float[n]),
      inverse_depth_per_m(new float[n]),
      flags(new std::uint8_t[n]),
      line_t_m(new float[n]),
      sample(kMaxRefitSamples),
      gap(n),
      cross(n),
      side(n),
      line{IndexList(n), IndexList(n)},
      scratch(n),
      band(n),
      values(new float[n]),
      wall_u_m(new float[n]),
      wall_v_m(new float[n]),
      column_run_first(new std::int32_t[kMaxWidth]),
      column_run_last(new std::int32_t[kMaxWidth]),
      column_run_width_m(new float[kMaxWidth]),
      column_run_peak_m(new float[kMaxWidth]),
      column_run_base_m(new float[kMaxWidth]),
      column_wall_pair_rows_down(new std::uint8_t[n]),
      score_x_m(new float[kMaxScoreSamples]),
      score_y_m(new float[kMaxScoreSamples]),
      score_z_m(new float[kMaxScoreSamples]),
      refit_x_m(new float[kMaxRefitSamples]),
      refit_y_m(new float[kMaxRefitSamples]),
      refit_z_m(new float[kMaxRefitSamples]) {}

std::size_t Workspace::bytes() const {
  return max_pixels * (sizeof(float) * 9 + sizeof(std::uint8_t) * 2 + sizeof(std::int32_t) * 7) +
         3 * sizeof(float) * (kMaxScoreSamples + kMaxRefitSamples) +
         sizeof(std::int32_t) * kMaxRefitSamples + 5 * 4 * kMaxWidth;
}

}  // namespace estimator
