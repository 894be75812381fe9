#pragma once
// A handrail is made to be gripped: its bar stands on two legs with a
// hand's clearance under it (the ISS bar's back is 4.35 cm off the surface
// it stands on). A fin at a rack's edge, a strip or a box edge is solid
// down to the surface. Seen from the side, the visible side face of a
// solid ridge runs on, pixel by pixel, below the bar's back height down
// toward the surface; past the bar's side face the view drops straight
// from the bar's back to the surface behind it (or to nothing). So, across
// the line in the image, each inlier walks outward over the bar's own
// pixels to its silhouette, skips the silhouette's pixel (a flying pixel
// there mixes the bar's return with the surface's and may land anywhere
// between), and reads the next kMinRampPx: all of them at heights in the
// clearance band (clearance_low_m to clearance_high_m above the line's
// mount) are a side face reaching down into the space a grip needs. The
// shares below are of inliers, not of rows. A leg is as solid as a fin:
// inliers within a leg's length of the visible extent's ends do not walk.
// Face-on, neither shape shows a side face, so the test only refuses where
// one shows.
#include <cstdint>

#include "estimator/config.hpp"
#include "estimator/handrail_pose.hpp"
#include "estimator/organized_cloud.hpp"
#include "estimator/pixel_scale.hpp"
#include "estimator/workspace.hpp"

namespace estimator {

struct BarClearance {
  // Per side of the line in the image (0: toward lower row or column
  // indices, 1: toward higher), the inliers whose walk reached the bar's
  // silhouette and how many of them then met a side face in the band.
  std::uint32_t walks[2] = {0, 0};
  std::uint32_t solid[2] = {0, 0};
  bool walks_rows = true;  // across the line along image rows (a line nearer vertical)
};

// Pixels of the clearance band needed in a row (after the skipped one),
// and how many of the bar's own pixels (its lower side face, below the
// line's inliers) a walk crosses before it gives up on a row.
constexpr int kMinRampPx = 2;
constexpr int kMaxBarPx = 6;
// Walks a side needs before its share judges anything.
constexpr std::uint32_t kMinClearanceWalks = 20;

// From the distances the search's gap pass wrote (ws.signed_distance_m,
// measured from the searched wall), moved by mount_shift_m to the line's
// own mount. Bounded: a few pixels per inlier, no memory.
BarClearance measure_bar_clearance(const OrganizedCloud& cloud, const DetectorConfig& cfg,
                                   const PixelScale& scale, const Workspace& ws,
                                   const CenterLine& line, const IndexList& inliers,
                                   float mount_shift_m);

// False when, on either side with enough walks, more than
// clearance_max_solid_fraction of them show a side face reaching down.
bool clearance_fits_bar(const BarClearance& clearance, const DetectorConfig& cfg);

}  // namespace estimator
