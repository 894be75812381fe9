#pragma once
// A handrail estimate (HANDRAIL_ESTIMATE) as the localization filter's
// measurement (estimator/localization/measurements.hpp): the detected
// handrail frame and depth features on the bar and on the wall behind it.
//
// The message carries the detected pose, not the depth points, so the
// features are points of the bar's model put where the detection says the
// bar is: on the centre line along the part of the bar in the camera's
// view, and on the wall plane beside it. The filter's residual (eqs. 6 to
// 10) compares each such point with where the mapped handrail and the
// filter's pose put it, so it measures exactly what the detection knows
// (its pose), at lever arms as long as the bar seen; with no end in view
// (NE) the filter drops the along-bar component (eqs. 11 to 13). Pure
// logic, fixed memory.
#include <Eigen/Geometry>
#include <cstdint>

#include "estimator/localization/measurements.hpp"
#include "hrp/handrail_estimate_t.hpp"

namespace fsw_app {

struct HandrailFeatureModel {
  double bar_length_m = 0.55;       // centre line, end to end
  double wall_offset_m = 0.061;     // centre line off the wall
  double wall_half_width_m = 0.06;  // wall features this far either side of the bar
  double ne_half_span_m = 0.15;     // NE: features this far either side of the origin
  int bar_points = 12;              // candidates along the bar (those in view kept)
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

// Fills *m from the estimate; *m is usable only with kOk.
HandrailMeasurementStatus handrail_measurement_from(
    const hrp::handrail_estimate_t& e, const HandrailFeatureModel& model,
    estimator::localization::HandrailMeasurement* m);

}  // namespace fsw_app
