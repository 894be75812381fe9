#include "estimator/track_past_end.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

namespace estimator {

namespace {
// The band across the walk, each side: 4 cm is 30 pixels at 0.3 m.
constexpr int kMaxHalfBandPx = 40;
// Heights kept per strip or flank and end (a 10 cm by 2 cm patch at 0.3 m
// is about 900 pixels; past this the first ones decide).
constexpr int kMaxHeights = 1024;

float median_of(float* values, std::uint32_t n) {
  if (n == 0) return 0.0f;
  float* mid = values + n / 2;
  std::nth_element(values, mid, values + n);
  return *mid;
}

struct Heights {
  float value[kMaxHeights];
  std::uint32_t n = 0;
  void add(float h) {
    if (n < kMaxHeights) value[n++] = h;
  }
};
}  // namespace

TrackPastEnd measure_track_past_end(const OrganizedCloud& cloud, const PixelScale& scale,
                                    const Workspace& ws, const Plane& wall, const CenterLine& line,
                                    const float end_t_m[2]) {
  TrackPastEnd m;
  if (!scale.ok) return m;
  const Eigen::Vector3f across = line.axis.cross(wall.normal);
  const int w = static_cast<int>(cloud.width), h = static_cast<int>(cloud.height);
  for (int end = 0; end < 2; ++end) {
    Heights strip, flank[2];
    const float out = end == 0 ? -1.0f : 1.0f;
    const Eigen::Vector3f from = line.point + (end_t_m[end] + out * kPastEndFromM) * line.axis;
    const Eigen::Vector3f to = line.point + (end_t_m[end] + out * kPastEndToM) * line.axis;
    if (!(from.z() > 0.0f && to.z() > 0.0f)) continue;
    const Eigen::Vector2f a(scale.fx_px * from.x() / from.z() + scale.cx_px,
                            scale.fy_px * from.y() / from.z() + scale.cy_px);
    const Eigen::Vector2f b(scale.fx_px * to.x() / to.z() + scale.cx_px,
                            scale.fy_px * to.y() / to.z() + scale.cy_px);
    const float length_px = (b - a).norm();
    if (!std::isfinite(length_px)) continue;
    const int steps = static_cast<int>(std::fmin(std::ceil(length_px), static_cast<float>(w + h)));
    const Eigen::Vector2f dir =
        length_px > 0.0f ? Eigen::Vector2f((b - a) / length_px) : Eigen::Vector2f(1.0f, 0.0f);
    const Eigen::Vector2f side(-dir.y(), dir.x());
    const float z_near = std::fmin(from.z(), to.z());
    const float half_px_f =
        std::fmax(scale.px_x(kPastEndFlankToM, z_near), scale.px_y(kPastEndFlankToM, z_near));
    const int half_px = std::min(kMaxHalfBandPx, static_cast<int>(std::ceil(half_px_f)) + 1);
    // Rounding puts a pixel in a band twice, or in two neighbouring bands:
    // it is judged once (this band's and the previous band's remembered).
    std::int32_t previous[2 * kMaxHalfBandPx + 1];
    std::int32_t current[2 * kMaxHalfBandPx + 1];
    int n_previous = 0;
    for (int k = 0; k <= steps; ++k) {
      const Eigen::Vector2f centre = a + static_cast<float>(k) * dir;
      int n_current = 0;
      for (int j = -half_px; j <= half_px; ++j) {
        const Eigen::Vector2f px = centre + static_cast<float>(j) * side;
        const int col = static_cast<int>(std::lround(px.x()));
        const int row = static_cast<int>(std::lround(px.y()));
        if (col < 0 || row < 0 || col >= w || row >= h) continue;
        const std::int32_t i = row * w + col;
        if (std::find(previous, previous + n_previous, i) != previous + n_previous ||
            std::find(current, current + n_current, i) != current + n_current) {
          continue;
        }
        current[n_current++] = i;
        if (!(ws.flags[i] & kFlagValid)) continue;
        const CloudPoint& q = cloud.points[i];
        const Eigen::Vector3f p(q.x_m, q.y_m, q.z_m);
        const Eigen::Vector3f r = p - line.point;
        const float past = out * (r.dot(line.axis) - end_t_m[end]);
        if (past < kPastEndFromM || past > kPastEndToM) continue;
        const float u = r.dot(across);
        const float u_abs = std::fabs(u);
        if (u_abs <= kPastEndStripHalfM) {
          strip.add(wall.signed_distance(p));
        } else if (u_abs >= kPastEndFlankFromM && u_abs <= kPastEndFlankToM) {
          flank[u > 0.0f ? 1 : 0].add(wall.signed_distance(p));
        }
      }
      std::copy(current, current + n_current, previous);
      n_previous = n_current;
    }
    m.strip_pixels[end] = strip.n;
    m.strip_m[end] = median_of(strip.value, strip.n);
    for (int s = 0; s < 2; ++s) {
      m.flank_pixels[end][s] = flank[s].n;
      m.flank_m[end][s] = median_of(flank[s].value, flank[s].n);
    }
  }
  return m;
}

bool track_runs_past_end(const TrackPastEnd& m, const bool end_seen[2], float track_top_m,
                         const DetectorConfig& cfg) {
  bool face_runs_on = false;
  for (int end = 0; end < 2; ++end) {
    if (!end_seen[end] || m.strip_pixels[end] < kPastEndMinPixels) continue;
    // Something as high as the bar's back over the track's top stands
    // over where the track would run: what lies under it is not seen.
    if (m.strip_m[end] - track_top_m >= gap_min_m(cfg)) continue;
    int level_flanks = 0;
    for (int s = 0; s < 2; ++s) {
      if (m.flank_pixels[end][s] < kPastEndMinPixels) continue;
      if (m.strip_m[end] - m.flank_m[end][s] >= 0.5f * cfg.mount_step_m) return true;
      ++level_flanks;
    }
    // Both flanks judged and level with the strip: one face runs on under
    // where the track would be. One flank alone may be a neighbouring face
    // flush with the track's top.
    face_runs_on = face_runs_on || level_flanks == 2;
  }
  return !face_runs_on;
}

}  // namespace estimator
