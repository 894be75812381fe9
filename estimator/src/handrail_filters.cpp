#include "estimator/handrail_filters.hpp"

#include <algorithm>
#include <cmath>

namespace estimator {
namespace {

struct Pixel {
  int row;
  int col;
};

Pixel pixel_of(const OrganizedCloud& cloud, std::int32_t i) {
  const int w = static_cast<int>(cloud.width);
  return {i / w, i % w};
}

bool inside(const OrganizedCloud& cloud, int row, int col) {
  return row >= 0 && col >= 0 && row < static_cast<int>(cloud.height) &&
         col < static_cast<int>(cloud.width);
}

// Nearest integer; inline (std::lround is a library call on the hot path).
int round_to_int(float x) {
  return static_cast<int>(x < 0.0f ? x - 0.5f : x + 0.5f);
}

// A pixel's noise, bounded to [0, 2 cm]; NaN counts as 0 (comparisons with
// NaN are false), so no bad value can open the windows.
float clamp_noise(float noise_m) {
  return noise_m >= 0.0f ? (noise_m < 0.02f ? noise_m : 0.02f) : 0.0f;
}

// Probes for the wall `offset_px` pixels away along (drow, dcol). A probe
// that lands outside the image (a bar near the image's edge) or on an
// invalid pixel (a dark or flying pixel at the bar's edge) moves back toward
// the bar and judges the first valid pixel, but never comes closer than half
// the offset: nearer, it could land on the bar itself.
bool probe_on_wall(const OrganizedCloud& cloud, const Workspace& ws, Pixel q, int drow, int dcol,
                   int offset_px, float wall_tolerance_m) {
  for (int k = offset_px; k >= (offset_px + 1) / 2; --k) {
    const int r = q.row + drow * k, c = q.col + dcol * k;
    if (!inside(cloud, r, c)) continue;
    const std::int32_t i = r * static_cast<int>(cloud.width) + c;
    if (!(ws.flags[i] & kFlagValid)) continue;
    return std::fabs(ws.signed_distance_m[i]) < wall_tolerance_m;
  }
  return false;
}

struct RaisedRun {
  float width_m = -1.0f;  // < 0: the run leaves the image, width unknown
  float peak_m = 0.0f;    // its highest point's distance from the wall
};

// The raised run through q along (drow, dcol): the 3-D distance between its
// two outermost raised pixels, plus one pixel's footprint since each
// outermost pixel centre lies half a pixel inside the silhouette; and its
// highest point above the wall.
RaisedRun measure_raised_run(const OrganizedCloud& cloud, const Workspace& ws, Pixel q, int drow,
                             int dcol, int max_steps, float raised_min_m, float footprint_m) {
  const int w = static_cast<int>(cloud.width);
  RaisedRun run;
  run.peak_m = ws.signed_distance_m[q.row * w + q.col];
  Pixel ends[2] = {q, q};
  for (int side = 0; side < 2; ++side) {
    const int sign = side == 0 ? -1 : 1;
    for (int k = 1; k <= max_steps; ++k) {
      const int r = q.row + sign * drow * k, c = q.col + sign * dcol * k;
      if (!inside(cloud, r, c)) return run;
      const std::int32_t i = r * w + c;
      if (!(ws.flags[i] & kFlagValid) || ws.signed_distance_m[i] < raised_min_m) break;
      run.peak_m = std::max(run.peak_m, ws.signed_distance_m[i]);
      ends[side] = {r, c};
    }
  }
  const CloudPoint& a = cloud.at(ends[0].row, ends[0].col);
  const CloudPoint& b = cloud.at(ends[1].row, ends[1].col);
  const float dx = a.x_m - b.x_m, dy = a.y_m - b.y_m, dz = a.z_m - b.z_m;
  run.width_m = std::sqrt(dx * dx + dy * dy + dz * dz) + footprint_m;
  return run;
}

}  // namespace

std::uint32_t gap_distance_test(const OrganizedCloud& cloud, const DetectorConfig& cfg,
                                const Plane& wall, Workspace& ws) {
  const float lo = gap_min_m(cfg), hi = gap_max_m(cfg);
  const float nx = wall.normal.x(), ny = wall.normal.y(), nz = wall.normal.z(), d = wall.d;
  std::uint32_t plane_inliers = 0;
  ws.gap.clear();
  for (std::int32_t i : ws.valid) {
    const CloudPoint& p = cloud.points[i];
    const float s = nx * p.x_m + ny * p.y_m + nz * p.z_m + d;
    ws.signed_distance_m[i] = s;
    if (std::fabs(s) < cfg.plane_inlier_m) {
      ws.flags[i] |= kFlagPlane;
      ++plane_inliers;
    }
    // A noisy pixel gets a wider window, by twice its own standard deviation.
    const float widen = 2.0f * clamp_noise(p.noise_m);
    if (s >= lo - widen && s <= hi + widen) {
      ws.flags[i] |= kFlagGap;
      ws.gap.push(i);
    }
  }
  return plane_inliers;
}

void cross_point_test(const OrganizedCloud& cloud, const DetectorConfig& cfg, const Plane& wall,
                      const PixelScale& scale, Workspace& ws) {
  const float d_c = cross_distance_m(cfg);
  const float l_h = cfg.handrail.bar_center_offset_m - 0.5f * cfg.handrail.bar_depth_m;
  const float nz = std::fmax(std::fabs(wall.normal.z()), 1e-3f);
  const float theta = std::atan(wall.normal.x() / nz);
  const float phi = std::atan(wall.normal.y() / nz);
  // Eq. 2: metric probe distances, widened on the side where the legs
  // appear when the wall is tilted.
  const float x_plus = std::fmax(d_c * std::cos(theta) - (l_h + d_c) * std::sin(theta), d_c);
  const float x_minus = std::fmax(d_c * std::cos(theta) + (l_h + d_c) * std::sin(theta), d_c);
  const float y_plus = std::fmax(d_c * std::cos(phi) - (l_h + d_c) * std::sin(phi), d_c);
  const float y_minus = std::fmax(d_c * std::cos(phi) + (l_h + d_c) * std::sin(phi), d_c);

  ws.cross.clear();
  for (std::int32_t i : ws.gap) {
    const Pixel q = pixel_of(cloud, i);
    const float z = cloud.points[i].z_m;
    const int xp = round_to_int(scale.px_x(x_plus, z));
    const int xm = round_to_int(scale.px_x(x_minus, z));
    const int yp = round_to_int(scale.px_y(y_plus, z));
    const int ym = round_to_int(scale.px_y(y_minus, z));
    const float tol = cfg.wall_tolerance_m;
    const bool x_ok =
        probe_on_wall(cloud, ws, q, 0, 1, xp, tol) && probe_on_wall(cloud, ws, q, 0, -1, xm, tol);
    const bool y_ok =
        probe_on_wall(cloud, ws, q, 1, 0, yp, tol) && probe_on_wall(cloud, ws, q, -1, 0, ym, tol);
    if (x_ok) ws.flags[i] |= kFlagCrossX;
    if (y_ok) ws.flags[i] |= kFlagCrossY;
    if (x_ok || y_ok) ws.cross.push(i);
  }
}

void side_width_test(const OrganizedCloud& cloud, const DetectorConfig& cfg,
                     const PixelScale& scale, Workspace& ws) {
  const HandrailGeometry& h = cfg.handrail;
  const float width_min = cfg.side_width_min_ratio * h.bar_width_m;
  const float width_max = cfg.side_width_max_ratio * std::fmax(h.bar_width_m, h.bar_depth_m);
  const float raised_min = gap_min_m(cfg);
  const float front = h.bar_center_offset_m + 0.5f * h.bar_depth_m;
  ws.side.clear();
  for (std::int32_t i : ws.cross) {
    const Pixel q = pixel_of(cloud, i);
    const float z = cloud.points[i].z_m;
    // The run's peak is the bar's front face (or a round bar's crown); a
    // cable or pipe of similar width at another height fails here. Noise
    // lifts the highest of a few samples, hence the pixel's sigma.
    const float peak_tolerance =
        cfg.run_peak_tolerance_m + 2.0f * clamp_noise(cloud.points[i].noise_m);
    auto passes = [&](const RaisedRun& run) {
      return run.width_m > width_min && run.width_m < width_max &&
             std::fabs(run.peak_m - front) < peak_tolerance;
    };
    bool pass = false;
    if (ws.flags[i] & kFlagCrossX) {
      const int steps = static_cast<int>(std::ceil(scale.px_x(width_max, z))) + 1;
      pass = passes(measure_raised_run(cloud, ws, q, 0, 1, steps, raised_min, z / scale.fx_px));
    }
    if (!pass && (ws.flags[i] & kFlagCrossY)) {
      const int steps = static_cast<int>(std::ceil(scale.px_y(width_max, z))) + 1;
      pass = passes(measure_raised_run(cloud, ws, q, 1, 0, steps, raised_min, z / scale.fy_px));
    }
    if (pass) {
      ws.flags[i] |= kFlagSide;
      ws.side.push(i);
    }
  }
}

}  // namespace estimator
