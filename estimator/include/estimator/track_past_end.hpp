#pragma once
// A seat track runs on past a handrail's ends.
//
// A bar seated on a seat track over a face (the front-height test's "a
// track step above a surface") claims a track under it. Seen face-on the
// track does not show beside the bar (2.6 cm wide under a 1.9 cm bar), so a
// handrail-like cable 7.5 to 9 cm over a face passes for a bar on a track
// hidden under it. But a seat track runs along the rack's edge, far longer
// than any handrail: just past a seen end it stands a track step proud of
// the face on at least one side of it (the face it stands on; a gap or a
// neighbouring face flush with its top may lie on the other). Past a cable's
// end the face runs on under where the track would be, level with its
// flanks.
//
// Measured differentially, the strip along the axis against its flanks at
// the same distance past the end, so that a wall normal a degree off (7 mm
// over the 40 cm from the line's middle) cancels.
#include <cstdint>

#include "estimator/config.hpp"
#include "estimator/handrail_pose.hpp"
#include "estimator/organized_cloud.hpp"
#include "estimator/pixel_scale.hpp"
#include "estimator/types.hpp"
#include "estimator/workspace.hpp"

namespace estimator {

// Past an end, from 1.5 cm (a leg's foot ends with the bar) to 10 cm. The
// strip: within 1 cm of the centre line across (a track is 2.6 cm wide);
// the flanks: 2 to 4 cm across on either side (past the track's edge).
constexpr float kPastEndFromM = 0.015f;
constexpr float kPastEndToM = 0.10f;
constexpr float kPastEndStripHalfM = 0.01f;
constexpr float kPastEndFlankFromM = 0.02f;
constexpr float kPastEndFlankToM = 0.04f;
// Pixels a strip or a flank needs for its median to count.
constexpr std::uint32_t kPastEndMinPixels = 8;

struct TrackPastEnd {
  // Per end (0: t_min's, 1: t_max's): median heights above the search's
  // wall of the strip and of each flank, and how many pixels each had.
  std::uint32_t strip_pixels[2] = {0, 0};
  std::uint32_t flank_pixels[2][2] = {{0, 0}, {0, 0}};
  float strip_m[2] = {0.0f, 0.0f};
  float flank_m[2][2] = {{0.0f, 0.0f}, {0.0f, 0.0f}};
};

// Every valid pixel of the region (too narrow for the frame's lattice
// sample): its middle line projected through the frame's pinhole fit
// (`scale`) and walked pixel by pixel, a band across it as wide as the
// flanks there plus a pixel, each pixel then placed by its own 3-D point.
// `wall` is the plane the search measures heights from; `end_t_m` where the
// bar ends along line.axis. Bounded by the image's size per end; the
// heights go into fixed buffers on the stack.
TrackPastEnd measure_track_past_end(const OrganizedCloud& cloud, const PixelScale& scale,
                                    const Workspace& ws, const Plane& wall, const CenterLine& line,
                                    const float end_t_m[2]);

// The verdict for a bar seated on a track over a face, over its seen ends
// with a strip of kPastEndMinPixels: true when at one of them the strip
// stands half a track step (cfg.mount_step_m) or more above a flank of
// kPastEndMinPixels; else false when at one of them both flanks have that
// many pixels and lie level with the strip (one face running on under
// where the track would be). One flank alone level with the strip may be a
// neighbouring face flush with the track's top; an end with too little to
// judge (cut by the image, dropouts, a gap) says nothing. So does an end
// whose strip stands at least gap_min_m(cfg) (the bar's back) over
// `track_top_m`, the hidden track's top (the bar's mount, in the strip's
// heights): something at the bar's own height stands over where the track
// would run (a box or a cable across the end), and a box's top
// is level across.
bool track_runs_past_end(const TrackPastEnd& m, const bool end_seen[2], float track_top_m,
                         const DetectorConfig& cfg);

}  // namespace estimator
