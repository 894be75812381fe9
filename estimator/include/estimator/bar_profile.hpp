#pragma once
// The ISS bar is deeper than it is wide: a rounded rectangle 3.5 cm along
// the wall normal by 1.9 cm across. Face-on, its front (8 mm corners) is as
// round as a 2 cm cable's and nothing tells the two apart. Seen from the
// side of the bar, though, its flat side face comes into view and the
// visible surface reaches down to the bar's back, 3.5 cm below its front;
// a round cable (0.6 to 2.5 cm thick) only ever shows its upper half, at
// most 1.25 cm deep. So where the view is oblique enough across the bar
// that the side face holds a fair share of the bar's pixels, the heights
// of the line's inliers above the wall must spread over more than a
// cable's radius. The test only refuses: noise widens the spread, so a far
// cable passes as before, and a round handrail geometry turns it off.
#include <cstdint>

#include "estimator/config.hpp"
#include "estimator/handrail_pose.hpp"
#include "estimator/organized_cloud.hpp"
#include "estimator/types.hpp"
#include "estimator/workspace.hpp"

namespace estimator {

struct BarProfile {
  // Angle between the camera's ray to the visible middle of the line and
  // the wall normal, in the plane across the bar (0: face-on).
  float obliquity_rad = 0.0f;
  // 10th to 90th percentile of the inliers' heights above `wall`, 1 mm
  // resolution; 0 when there are no inliers.
  float spread_m = 0.0f;
  std::uint32_t count = 0;
};

// From the distances the search's gap pass wrote (ws.signed_distance_m,
// measured from `wall`) at the line's inliers. Fixed memory (a histogram
// on the stack), one pass over the inliers.
BarProfile measure_bar_profile(const Workspace& ws, const Plane& wall, const CenterLine& line,
                               const IndexList& inliers);

// False only for a profile too shallow for the configured bar at an
// obliquity of at least profile_min_obliquity_deg; always true for a bar
// no deeper than 1.3 times its width (a round bar shows no side face).
bool profile_fits_bar(const BarProfile& profile, const DetectorConfig& cfg);

}  // namespace estimator
