#include "estimator/bar_runs.hpp"

#include <algorithm>
#include <cmath>

#include "run_levels.hpp"

namespace estimator {
namespace {

// Neighbouring pixels on one surface differ by less than this plus twice
// their noise: a bar's own front and side faces step a few millimetres a
// pixel, the drop from its edge to the surface behind is 3.75 cm or more.
constexpr float kJumpM = 0.02f;

using run_levels::level_beside_end;

struct RunLimits {
  float width_min_m, width_max_m;
  float min_rise_m;
  float depth_m;  // the bar's depth, plus a margin: how far below the peak its pixels reach
  float pixel_angle_rad;
};

// One line of n pixels (a row or a column, stride apart from base): marks
// `flag` on the pixels of every run that passes.
void mark_runs_on_line(const OrganizedCloud& cloud, const RunLimits& lim, Workspace& ws,
                       std::int32_t base, int stride, int n, std::uint8_t flag) {
  const float* height_m = ws.signed_distance_m.get() + base;
  // Twice each pixel's bounded noise, from the distance pass: the jump
  // test reads two streams of floats instead of the cloud's wider points.
  const float* widen_m = ws.gap_widen_m.get() + base;
  std::uint8_t* flags = ws.flags.get() + base;
  int first = 0;
  while (first < n) {
    if (!(height_m[first * stride] > -INFINITY)) {
      ++first;
      continue;
    }
    // The run: valid neighbours, each within a jump of the one before.
    int last = first;
    float peak_m = height_m[first * stride];
    while (last + 1 < n) {
      const float next = height_m[(last + 1) * stride];
      const float here = height_m[last * stride];
      const float jump = kJumpM + widen_m[last * stride];
      if (!(next > -INFINITY) || std::fabs(next - here) > jump) break;
      peak_m = std::max(peak_m, next);
      ++last;
    }
    const int run_first = first;
    first = last + 1;
    // A run that reaches the image's edge has no known width.
    if (run_first == 0 || last == n - 1) continue;
    const CloudPoint& a = cloud.points[base + run_first * stride];
    const CloudPoint& b = cloud.points[base + last * stride];
    // Quick reject on pixels: the widest bar spans width_max * f / z.
    const float dx = a.x_m - b.x_m, dy = a.y_m - b.y_m, dz = a.z_m - b.z_m;
    const float footprint_m = 0.5f * (a.z_m + b.z_m) * lim.pixel_angle_rad;
    const float width_m = std::sqrt(dx * dx + dy * dy + dz * dz) + footprint_m;
    if (!(width_m > lim.width_min_m && width_m < lim.width_max_m)) continue;
    const float before = level_beside_end(height_m, stride, n, run_first, -1);
    const float after = level_beside_end(height_m, stride, n, last, 1);
    // fmax of NaN and a number is the number: one side's level will do.
    const float higher = std::fmax(before, after);
    if (!(peak_m - higher >= lim.min_rise_m)) continue;
    for (int k = run_first; k <= last; ++k) {
      if (height_m[k * stride] >= peak_m - lim.depth_m) flags[k * stride] |= flag;
    }
  }
}

}  // namespace

float bar_run_min_rise_m(const DetectorConfig& cfg) {
  return bar_front_min_m(cfg.handrail) - cfg.handrail.bar_depth_m - 0.01f;
}

void find_bar_runs(const OrganizedCloud& cloud, const DetectorConfig& cfg, const PixelScale& scale,
                   Workspace& ws) {
  const HandrailGeometry& h = cfg.handrail;
  RunLimits lim;
  lim.width_min_m = cfg.side_width_min_ratio * h.bar_width_m;
  lim.width_max_m = cfg.side_width_max_ratio * std::fmax(h.bar_width_m, h.bar_depth_m);
  lim.min_rise_m = bar_run_min_rise_m(cfg);
  lim.depth_m = h.bar_depth_m + 0.01f;
  const int width = static_cast<int>(cloud.width), height = static_cast<int>(cloud.height);
  constexpr std::uint8_t kCleared =
      static_cast<std::uint8_t>(~(kFlagCrossX | kFlagCrossY | kFlagSide | kFlagLine));
  for (std::size_t i = 0; i < cloud.size(); ++i) ws.flags[i] &= kCleared;
  lim.pixel_angle_rad = 1.0f / scale.fx_px;
  for (int r = 0; r < height; ++r) {
    mark_runs_on_line(cloud, lim, ws, r * width, 1, width, kFlagCrossX);
  }
  lim.pixel_angle_rad = 1.0f / scale.fy_px;
  for (int c = 0; c < width; ++c) {
    mark_runs_on_line(cloud, lim, ws, c, width, height, kFlagCrossY);
  }
  ws.side.clear();
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    if (ws.flags[i] & (kFlagCrossX | kFlagCrossY)) {
      ws.flags[i] |= kFlagSide;
      ws.side.push(static_cast<std::int32_t>(i));
    }
  }
}

}  // namespace estimator
