#pragma once
// Bar-first candidates: pixels that look like a handrail's bar from what
// lies right around them, with no wall window. Along a row or a column of
// the image a bar is a short continuous run (its front face, and its side
// face when seen obliquely) that stands clear of what lies just beyond both
// of its ends: the open space between a bar and the surface under it is at
// least the bar's clearance deep wherever the camera looks past the bar.
// Nothing here assumes which surface the bar stands on, how far that
// surface is from the dominant plane, or what stands beside it.
#include "estimator/config.hpp"
#include "estimator/organized_cloud.hpp"
#include "estimator/pixel_scale.hpp"
#include "estimator/workspace.hpp"

namespace estimator {

// The least rise of a bar's highest point over the higher of the two
// levels just past its run's ends: the back face's clearance over the
// surface its legs stand on (the front's least height less the bar's
// depth), less a centimetre for a neighbouring strip a little proud of
// that surface and for noise.
float bar_run_min_rise_m(const DetectorConfig& cfg);

// Along every row and every column: each run of valid pixels whose
// neighbours differ by less than a jump (2 cm plus twice the noise) that
// is as wide as the bar (side_width_min_ratio .. side_width_max_ratio, the
// 3-D distance across it) and whose highest point stands at least
// bar_run_min_rise_m() over the levels 2 to 4 pixels past both its ends
// (one, if the other side shows nothing valid) marks its pixels within the
// bar's depth of that highest point. Heights are ws.signed_distance_m (to
// the dominant plane; the run's rise is a difference, so the plane's offset
// does not matter), and the jump's noise is ws.gap_widen_m, both as
// gap_distance_test() leaves them. Writes ws.side in ascending order and the flags
// kFlagCrossX (a row's run), kFlagCrossY (a column's) and kFlagSide.
void find_bar_runs(const OrganizedCloud& cloud, const DetectorConfig& cfg, const PixelScale& scale,
                   Workspace& ws);

}  // namespace estimator
