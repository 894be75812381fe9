#pragma once
// Handrail geometry and detector thresholds. Every number the detector uses
// lives here; the defaults are documented in estimator/README.md.
#include <cstdint>

namespace estimator {

// Geometry of the bar, in the handrail frame: x = wall normal, z = along the
// bar. Two kinds ship: the paper's round model and the real ISS bar.
struct HandrailGeometry {
  float bar_width_m;          // across the bar, parallel to the wall
  float bar_depth_m;          // along the wall normal
  float bar_center_offset_m;  // centre line's distance from the wall
  float bar_length_m;         // between the centre-line end points
};

// The paper's model: round bar 3.5 cm across on 6.5 cm legs.
HandrailGeometry paper_round_handrail(float bar_length_m = 0.55f);
// The ISS bar: rounded rectangle 3.5 cm deep by 1.9 cm across, centre line
// 6.1 cm off the wall.
HandrailGeometry iss_handrail(float bar_length_m = 0.55f);

struct DetectorConfig {
  HandrailGeometry handrail = iss_handrail();

  // Input gating.
  float min_range_m = 0.10f;
  float max_range_m = 2.00f;

  // Plane estimation (RANSAC over 3 points, then least squares on inliers).
  std::uint32_t plane_iterations = 40;
  std::uint32_t plane_score_samples = 800;  // points scored per hypothesis
  float plane_inlier_m = 0.015f;
  float plane_min_inlier_fraction = 0.20f;

  // Gap distance test (eq. 1): the bar's visible surface lies between
  // offset - depth/2 and offset + depth/2 from the wall, widened by this
  // margin plus twice the pixel's noise.
  float gap_margin_m = 0.008f;

  // Cross point test (eqs. 2, 3). d_c = sqrt(2) b_D + delta.
  float cross_delta_m = 0.035f;
  float wall_tolerance_m = 0.02f;  // d_g,min: "on the wall"

  // Side width test (eq. 4) on the raised span through the pixel.
  float side_width_min_ratio = 0.6f;  // x bar width
  float side_width_max_ratio = 1.6f;  // x max(bar width, bar depth)
  // ... and the run's highest point must be the bar's front face, within
  // this plus twice the pixel's noise.
  float run_peak_tolerance_m = 0.012f;

  // Handrail candidates (Algorithm 2) and clustering (Algorithm 1).
  std::uint32_t line_iterations = 80;
  std::uint32_t line_score_samples = 600;
  std::uint32_t line_attempts = 6;  // searches after rejected lines
  float line_inlier_m = 0.015f;
  float cluster_gap_m = 0.05f;              // d_r
  float beam_length_min_ratio = 0.75f;      // b_H,min / b_H when both ends seen
  float beam_length_max_ratio = 1.25f;      // b_H,max / b_H
  float min_visible_length_m = 0.08f;       // shorter segments are clutter
  float front_height_tolerance_m = 0.004f;  // bar front face vs geometry
  std::uint32_t min_line_inliers = 25;

  // Selection by the gripper's angle psi_p: 0 = handrails along image y.
  float gripper_angle_rad = 0.0f;

  // End detection: how far past the bar's last pixel to look for the wall.
  float end_search_m = 0.10f;

  // Target pose: p_g = p_c + d_c v_P.
  float target_standoff_m = 0.35f;

  // Random numbers are seeded per frame from this and the frame id, so a
  // frame gives the same answer whenever it is processed.
  std::uint64_t seed = 0x5eed2024u;

  // Largest frame the detector is sized for.
  std::uint32_t max_width = 224;
  std::uint32_t max_height = 171;

  // Per-frame budget; 0 = no budget.
  std::int64_t budget_us = 0;
};

// Derived thresholds (one place, so tests and tools agree).
float gap_min_m(const DetectorConfig& cfg);
float gap_max_m(const DetectorConfig& cfg);
float cross_distance_m(const DetectorConfig& cfg);  // d_c

// Checks ranges and relations; returns nullptr when valid, otherwise the
// name of the first offending field.
const char* validate(const DetectorConfig& cfg);

}  // namespace estimator
