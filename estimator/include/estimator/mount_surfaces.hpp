#pragma once
// Where the handrail may stand: the mount hypotheses of a frame.
//
// The detector's tests measure heights from the surface the bar stands on.
// On a flat wall that is the dominant plane; on an ISS rack wall it is a
// seat track 1.3 cm proud of one rack's face, while the faces around it
// differ by 1 to 5 cm and fill most of the view. The faces are parallel, so
// every surface in view is a peak in the histogram of the pixels' distances
// along the dominant plane's normal. Each peak near the plane is a mount,
// and so is a seat track on it; a mount is worth trying where the bar's
// front face, at its height, would find pixels.
#include <cstdint>

#include "estimator/config.hpp"
#include "estimator/organized_cloud.hpp"
#include "estimator/workspace.hpp"

namespace estimator {

constexpr std::uint32_t kMaxSurfacePeaks = 8;
// Two mounts closer than this are one (the histogram's resolution); a mount
// this near the dominant plane is the plane.
constexpr float kSameMountM = 0.004f;

struct MountHypotheses {
  // The surfaces in view: distances of the histogram's peaks from the
  // dominant plane, in the order found (nearest the wall first).
  std::uint32_t surface_count = 0;
  float surface_m[kMaxSurfacePeaks] = {};
  std::uint32_t count = 0;
  // Distance of each mount from the dominant plane, along its normal (> 0:
  // toward the camera), best first.
  float offset_m[kMaxMountHypotheses] = {};
  // Pixels where that mount puts the bar's front face.
  std::uint32_t front_pixels[kMaxMountHypotheses] = {};
  // What ranked the mount: in a bay view those pixels less the ones in as
  // wide a window just above it, where nothing of a bar on that mount lies
  // (find_mount_hypotheses); elsewhere the pixels themselves.
  std::uint32_t rank_pixels[kMaxMountHypotheses] = {};
  // How many of the mounts, the last ones, were read off bar-front peaks
  // rather than surfaces (add_front_peak_mounts).
  std::uint32_t front_peak_count = 0;
  // ... and where the dominant plane itself puts it.
  std::uint32_t dominant_front_pixels = 0;
};

// Histogram bins: 2.5 mm over the dominant plane's +-(mount_search_m +
// bar height + mount_step_m); fixed size, on the stack.
constexpr int kMountHistogramBins = 256;
constexpr float kMountBinM = 0.0025f;

// From ws.signed_distance_m (the distances to the dominant plane that the
// gap distance pass wrote for every pixel; -infinity where invalid). The
// dominant plane itself (offset 0) is always a hypothesis, so a flat wall
// is tried as before; a hypothesis needs at least min_line_inliers front
// pixels unless it is that one. Past the surface mounts, up to
// front_peak_mounts more are read off bar-front peaks that no surface
// mount explains (the last front_peak_count of them).
MountHypotheses find_mount_hypotheses(const OrganizedCloud& cloud, const DetectorConfig& cfg,
                                      const Workspace& ws);

// The surface a bar stands on, from the height of its front face above the
// dominant plane: a surface in view the bar's front height (centre-line
// offset + depth / 2) below it, or a seat track mount_step_m proud of such
// a surface, or on the dominant plane. True, with *mount_m its distance
// from the plane, when the nearest of those is within tolerance_m and is
// not the dominant plane itself (a bar on it is judged by the flat-wall
// rules, with the dominant plane as the wall); false otherwise.
// `near_levels` (count `near_count`, from the dominant plane) are surfaces
// measured right beside the bar (mount_beside.hpp), judged like those in
// view.
// *on_track_out (when given) says whether the mount found is a seat track
// a step above a surface rather than a surface itself.
bool find_mount_under_bar(const MountHypotheses& mounts, const DetectorConfig& cfg, float front_m,
                          float tolerance_m, float* mount_m, const float* near_levels = nullptr,
                          std::uint32_t near_count = 0, bool* on_track_out = nullptr);

}  // namespace estimator
