#pragma once
// A handrail stands on its mount, so the mount shows beside it.
//
// The front-height test (mount_surfaces.hpp) asks only that some surface in
// view lie a handrail's height below the bar's front face. With two or
// three faces at different depths in every rack-wall view, some surface
// nearly always does, whatever stands there: a rack's edge strip beside a
// groove, a cable bridging at handrail height over another face. A real
// handrail stands on that surface (a seat track on a rack face, or a flat
// wall): in a band beside the bar, past the track's half width, the pixels
// on at least one side lie on the mount or on the face the track stands
// on. The bar's own shadow can hide one side, never both. Fewer sampled
// pixels in both bands than the test needs is no evidence either way.
#include <cstdint>

#include "estimator/config.hpp"
#include "estimator/handrail_pose.hpp"
#include "estimator/organized_cloud.hpp"
#include "estimator/types.hpp"
#include "estimator/workspace.hpp"

namespace estimator {

struct MountBeside {
  // Per side of the bar (across it, in the wall plane): the lattice sample's
  // valid pixels in the band, and of them those on the mount's own level
  // and those on a seat track's foot below it (each pixel to the nearer).
  std::uint32_t band_pixels[2] = {0, 0};
  std::uint32_t at_level[2] = {0, 0};
  std::uint32_t at_foot[2] = {0, 0};
  // On either: what shows the bar stands there.
  std::uint32_t at_mount(int side) const { return at_level[side] + at_foot[side]; }
};

// From the lattice sample (ws.sample). `wall` is the plane the search
// measures heights from, `mount_above_wall_m` the mount's height above it;
// `line` the candidate's centre line (its visible extent t_min..t_max).
MountBeside measure_mount_beside(const OrganizedCloud& cloud, const DetectorConfig& cfg,
                                 const Workspace& ws, const Plane& wall, const CenterLine& line,
                                 float mount_above_wall_m);

// The verdict: enough of either side's band on the mount, or too few
// pixels in both bands to tell.
bool mount_shows_beside(const MountBeside& m, const DetectorConfig& cfg);

// Whether the band reads as a bar on a seat track, for a bar seated on a
// face other than the dominant plane (cfg.track_beside): false when a
// judged side has mount_beside_min_fraction of its pixels on the mount's
// own level, and more there than on a track's foot, and no judged side
// shows the foot so (that fraction, and more than on the level). The ISS
// handrails on rack walls stand on seat tracks 2.6 cm wide and 1.3 cm
// proud; past the track's edge lies the rack face a step lower, or a gap.
// A handrail-like cable seated on the face under it has that face running
// on beside it at the mount's level. A neighbouring face may lie flush
// with the track's top (faces differ by 1 to 5 cm, a track stands 1.3 cm
// proud) and run on at the mount's level on that side; the track's own
// face then shows on the other.
bool track_shows_beside(const MountBeside& m, const DetectorConfig& cfg);

// Whether the band reads as one unbroken face under the bar: both sides
// judged (track_beside_min_pixels each), each with mount_beside_min_fraction
// of its pixels on the mount's own level and more there than on a track's
// foot. For a bar seated on the dominant plane's own face in a view of rack
// faces (cfg.track_beside): a handrail's seat track shows a step beside it
// on at least one side (the track's own face a step below, a gap or another
// rack), even where the neighbouring face lies flush with the track's top
// and is the plane; a cable lying over a face has that face on both sides.
bool open_face_both_sides(const MountBeside& m, const DetectorConfig& cfg);

// The surfaces right beside the bar, for the front-height test. The
// surfaces in view (mount_surfaces.hpp) are the frame's histogram peaks,
// measured from the dominant plane: a rack's 9 cm frame strip under the
// track can hold too few pixels to make a peak of its own, or blur into the
// panel a centimetre from it, and where that plane is tilted by a degree a
// surface's distance from it changes by millimetres across the view. The
// level beside the bar is measured where the bar is and is what it stands
// on. Per side: the most populated level of the band's sampled pixels (2.5
// mm bins, smoothed over three) between lo_m and hi_m from `wall`, the
// mean of the pixels within 5 mm of it, when those are at least
// mount_beside_min_fraction of that side's band and mount_beside_min_pixels.
struct LevelsBeside {
  std::uint32_t count = 0;
  float level_m[2] = {0.0f, 0.0f};  // from `wall`, along its normal
};
LevelsBeside find_levels_beside(const OrganizedCloud& cloud, const DetectorConfig& cfg,
                                const Workspace& ws, const Plane& wall, const CenterLine& line,
                                float lo_m, float hi_m);

}  // namespace estimator
