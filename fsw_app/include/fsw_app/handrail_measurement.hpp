#pragma once
// A handrail estimate (HANDRAIL_ESTIMATE) as the localization filter's
// measurement (estimator/localization/measurements.hpp): the detected
// handrail frame and depth features on the bar and on the wall behind it.
//
// The message carries the detected pose, not the depth points, so the
// features are points of the bar's model put where the detection says the
// bar is: on the centre line along the part of the bar in the camera's
// view, and on the wall plane either side of it. The filter's residual
// (eqs. 6 to 10) compares each such point with where the mapped handrail
// and the filter's pose put it, so it measures what the detection knows
// (its pose), at lever arms as long as the bar seen and as wide as the wall
// seen; with no end in view (NE) the filter drops the along-bar component
// (eqs. 11 to 13). Pure logic, fixed memory.
//
// Why the wall features sit as far out as the camera sees: the bar's
// features lie on one line and say nothing of the rotation about it; only
// the wall's do, by their depth either side. That rotation, times the range
// to the bar, is the body's position error across the bar. The detection's
// wall normal comes from a plane fitted across the image (hreval: 0.4 to 0.9
// deg off on rack walls); wall features 6 cm either side told the filter
// about 3 deg a frame, and in the dynamic test the body's error across the
// bar wandered by up to 2.5 mm with the IMU's noise between seeds.
#include <Eigen/Geometry>
#include <cstdint>

#include "estimator/localization/measurements.hpp"
#include "hrp/handrail_estimate_t.hpp"

namespace fsw_app {

struct HandrailFeatureModel {
  double wall_offset_m = 0.061;  // centre line off the wall
  // Wall features either side of the bar: the widest of kWallSteps offsets,
  // from wall_half_width_m down to wall_min_half_width_m, that is in view.
  double wall_half_width_m = 0.20;
  double wall_min_half_width_m = 0.06;
  static constexpr int kWallSteps = 4;
  double ne_half_span_m = 0.15;  // NE: features this far either side of the origin
  int bar_points = 12;           // candidates along the bar (those in view kept)
  // The camera's field of view (the Pico Flexx: 62 x 45 deg) and the
  // nearest depth it measures.
  double half_fov_x_rad = 31.0 * 3.14159265358979323846 / 180.0;
  double half_fov_y_rad = 22.5 * 3.14159265358979323846 / 180.0;
  double min_range_m = 0.1;
};

enum class HandrailMeasurementStatus : std::uint8_t {
  kOk,
  kNoHandrail,  // NH, or a detection that did not finish (deadline)
  kNotInView,   // too few of the model's points in the camera's view
};
const char* to_string(HandrailMeasurementStatus s);

// Fills *m from the estimate; *m is usable only with kOk. bar_length_m is
// the bar's length learned from estimates with both ends seen
// (bar_length_tally.hpp), negative when not known: an OE estimate then
// becomes NE (the centre is half a bar from the seen end, so without the
// length the position along the bar is not known).
HandrailMeasurementStatus handrail_measurement_from(
    const hrp::handrail_estimate_t& e, const HandrailFeatureModel& model, double bar_length_m,
    estimator::localization::HandrailMeasurement* m);

}  // namespace fsw_app
