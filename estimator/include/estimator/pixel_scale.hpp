#pragma once
// The image's projection, recovered from the cloud itself: column =
// cx + fx * x / z (and the same for rows), fitted by least squares over the
// valid points. The detector needs pixels-per-metre to place the cross and
// side probes, and this way it assumes no image size, principal point or
// lens: it works on any organized cloud, recorded or live.
#include "estimator/organized_cloud.hpp"
#include "estimator/workspace.hpp"

namespace estimator {

struct PixelScale {
  bool ok = false;
  float fx_px = 0.0f, cx_px = 0.0f;
  float fy_px = 0.0f, cy_px = 0.0f;
  // Pixels spanned by a length at range z (x and y directions).
  float px_x(float length_m, float z_m) const { return fx_px * length_m / z_m; }
  float px_y(float length_m, float z_m) const { return fy_px * length_m / z_m; }
};

PixelScale estimate_pixel_scale(const OrganizedCloud& cloud, const IndexList& valid);

}  // namespace estimator
