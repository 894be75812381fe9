#include "estimator/bar_clearance.hpp"

#include <cmath>

namespace estimator {
namespace {

// The walk from inlier pixel (row, col) outward by (drow, dcol): over the
// bar's own pixels (at or above the band, at most kMaxBarPx of them), then
// past the silhouette's pixel, then kMinRampPx pixels in the band or not.
// -1: nothing to judge (the image's edge, or still raised); 0: the bar
// ends in a drop; 1: a side face runs on into the band.
int walk_from_edge(const float* height_m, int width, int height, int row, int col, int drow,
                   int dcol, float band_low_m, float band_high_m) {
  auto inside = [&](int r, int c) {
    return static_cast<unsigned>(r) < static_cast<unsigned>(height) &&
           static_cast<unsigned>(c) < static_cast<unsigned>(width);
  };
  int r = row + drow, c = col + dcol;
  int bar_px = 0;
  while (inside(r, c) && height_m[r * width + c] >= band_high_m) {
    if (++bar_px > kMaxBarPx) return -1;
    r += drow;
    c += dcol;
  }
  if (!inside(r, c)) return -1;
  // (r, c) is the silhouette's pixel: skipped.
  for (int k = 0; k < kMinRampPx; ++k) {
    r += drow;
    c += dcol;
    if (!inside(r, c)) return -1;
    const float h = height_m[r * width + c];
    if (!(h >= band_low_m && h < band_high_m)) return 0;
  }
  return 1;
}

}  // namespace

BarClearance measure_bar_clearance(const OrganizedCloud& cloud, const DetectorConfig& cfg,
                                   const PixelScale& scale, const Workspace& ws,
                                   const CenterLine& line, const IndexList& inliers,
                                   float mount_shift_m) {
  BarClearance out;
  // The line's direction in the image, from two points on it.
  const Eigen::Vector3f a = line.point, b = line.point + 0.1f * line.axis;
  if (!(a.z() > 0.0f && b.z() > 0.0f)) return out;
  const float du = scale.fx_px * (b.x() / b.z() - a.x() / a.z());
  const float dv = scale.fy_px * (b.y() / b.z() - a.y() / a.z());
  out.walks_rows = std::fabs(du) <= std::fabs(dv);
  const int drow = out.walks_rows ? 0 : 1, dcol = out.walks_rows ? 1 : 0;
  const int width = static_cast<int>(cloud.width), height = static_cast<int>(cloud.height);
  // The band in the search's distances.
  const float band_low = cfg.clearance_low_m + mount_shift_m;
  const float band_high = cfg.clearance_high_m + mount_shift_m;
  const float* distance_m = ws.signed_distance_m.get();
  // A leg is solid from the bar down to its mount: inliers within a leg's
  // length (end_drop_max_m) of either end of the visible extent are left
  // out, where an end may stand.
  const float t_from = line.t_min_m + cfg.end_drop_max_m;
  const float t_to = line.t_max_m - cfg.end_drop_max_m;
  for (std::int32_t i : inliers) {
    const CloudPoint& p = cloud.points[i];
    const float t = (p.x_m - a.x()) * line.axis.x() + (p.y_m - a.y()) * line.axis.y() +
                    (p.z_m - a.z()) * line.axis.z();
    if (!(t >= t_from && t <= t_to)) continue;
    const int row = i / width, col = i - row * width;
    for (int side = 0; side < 2; ++side) {
      const int sign = side == 0 ? -1 : 1;
      const int v = walk_from_edge(distance_m, width, height, row, col, sign * drow, sign * dcol,
                                   band_low, band_high);
      if (v < 0) continue;
      ++out.walks[side];
      out.solid[side] += static_cast<std::uint32_t>(v);
    }
  }
  return out;
}

bool clearance_fits_bar(const BarClearance& clearance, const DetectorConfig& cfg) {
  for (int side = 0; side < 2; ++side) {
    if (clearance.walks[side] < kMinClearanceWalks) continue;
    if (static_cast<float>(clearance.solid[side]) >
        cfg.clearance_max_solid_fraction * static_cast<float>(clearance.walks[side])) {
      return false;
    }
  }
  return true;
}

}  // namespace estimator
