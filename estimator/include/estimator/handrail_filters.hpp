#pragma once
// Step 2: the three tests that keep only points that look like a handrail
// bar standing off the wall.
#include "estimator/config.hpp"
#include "estimator/organized_cloud.hpp"
#include "estimator/pixel_scale.hpp"
#include "estimator/types.hpp"
#include "estimator/workspace.hpp"

namespace estimator {

// Gap distance test (eq. 1): points whose distance from the wall is that of
// the bar's visible surface. It is the detector's one pass over every
// pixel, so it also judges validity (setting the frame's flags afresh,
// counting the valid pixels into *valid_pixels), writes the signed distance
// to the wall (ws.signed_distance_m) and each pixel's 1 / z
// (ws.inverse_depth_per_m, for the cross test), and marks the wall's inliers
// (kFlagPlane) and the pixels the cross test's probes accept as wall
// (kFlagWall). cloud -> ws.gap; returns the number of wall inliers.
std::uint32_t gap_distance_test(const OrganizedCloud& cloud, const DetectorConfig& cfg,
                                const Plane& wall, Workspace& ws, std::uint32_t* valid_pixels);

// The same pass against the wall offset_m from the dominant plane along its
// normal (a mount on a rack wall), from what the pass against the dominant
// plane kept (ws.plane_distance_m, ws.gap_widen_m: keep_plane_pass()
// first), without reading the cloud again. Same outputs; kFlagPlane and
// the returned count stay the dominant plane's. One difference: when
// plane_left_out_of_gap_list(), the dominant plane's inliers keep their gap
// bit (the probes read it) but are left out of ws.gap.
//
// faces_m (face_count of them, distances from the dominant plane): the
// surfaces in view (MountHypotheses::surface_m). A pixel on one of them
// (within 5 mm plus its noise) standing above the wall tolerance but below
// the gap window over this mount is wall to the cross test's probes too:
// beside a seat track on a rack the probe lands on a neighbouring face 2
// to 3.5 cm over the track's face as often as on that face.
// Only faces, not any height below the window: taking every pixel below
// the window as wall (eq. 3's d_g,min read as the window's lower edge) let
// cables beside boxes through, three times the false detections of this.
std::uint32_t gap_distance_shifted(const OrganizedCloud& cloud, const DetectorConfig& cfg,
                                   float offset_m, Workspace& ws, std::uint32_t* valid_pixels,
                                   const float* faces_m = nullptr, std::uint32_t face_count = 0);

// Whether any of the surfaces in view would be the probes' wall on the
// mount offset_m from the dominant plane (see gap_distance_shifted).
bool faces_beside_mount(const DetectorConfig& cfg, float offset_m, const float* faces_m,
                        std::uint32_t face_count);

// Whether a search offset_m from the dominant plane leaves the plane's own
// inliers out of its gap list: when a bar on that mount would have its
// front face clear of the plane's inlier band (plane_inlier_m) by
// kPlaneBandClearanceM. A search on a face a few centimetres deeper than
// the dominant plane puts the whole plane inside its gap window (3.5 to
// 8.7 cm above the mount), and the cross test would judge every pixel of
// it, at half a frame per search; yet no bar's front can be among them.
// A bar on that mount loses only the part of its sides inside the band.
// The deepest mount searched is mount_search_m (5.2 cm) below the plane,
// where an ISS bar's front stands 2.6 cm above it: every mount searched
// qualifies. The plane's own search (offset 0) keeps them.
constexpr float kPlaneBandClearanceM = 0.01f;
bool plane_left_out_of_gap_list(const DetectorConfig& cfg, float offset_m);
// Keeps the last gap distance pass's distances (made against the dominant
// plane) for gap_distance_shifted().
void keep_plane_pass(const OrganizedCloud& cloud, Workspace& ws);

// Cross point test (eqs. 2, 3): both probes to either side of the pixel, in
// image x or in image y, land on the wall. Probe offsets widen on the side
// where the wall's tilt would put a leg. ws.gap -> ws.cross, and the
// kFlagCrossX / kFlagCrossY bits say which direction passed. Reads the
// pixels' inverse depth written by gap_distance_test() on this cloud.
void cross_point_test(const OrganizedCloud& cloud, const DetectorConfig& cfg, const Plane& wall,
                      const PixelScale& scale, Workspace& ws);

// Where the side width test expects a bar's front face: a bar's height
// above the surface searched, or also a bar's height above a deeper face
// shown right beside the run (a bar standing on a face behind the one
// searched; the line's own height test seats it later, seat_on_mount).
enum class FrontFace { kOnSearchedSurface, kOnSearchedOrDeeper };

// Side width test (eq. 4): along each direction that passed the cross test,
// the raised run through the pixel must be as wide as the bar, and (our
// addition) its highest point must be at the bar's front-face height above
// the searched surface or, with kOnSearchedOrDeeper, above the level just
// beyond the run's ends where that level is deeper than the searched
// surface's window. ws.cross -> ws.side.
void side_width_test(const OrganizedCloud& cloud, const DetectorConfig& cfg,
                     const PixelScale& scale, Workspace& ws,
                     FrontFace front_face = FrontFace::kOnSearchedSurface);

}  // namespace estimator
