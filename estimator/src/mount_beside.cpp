#include "estimator/mount_beside.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

namespace estimator {

namespace {
// The pixels' noise widens the level's tolerance by twice its sigma, up to
// this (at 1.5 m the depth renderer's sigma is near a centimetre).
constexpr float kMaxNoiseWidening_m = 0.01f;

// The band beside a bar: a pixel's side of the centre line (0 or 1, across
// it in the wall's plane) when it lies along the line's visible extent and
// mount_beside_min_m to mount_beside_max_m across; -1 otherwise.
struct BandBeside {
  const DetectorConfig& cfg;
  const CenterLine& line;
  Eigen::Vector3f across;
  BandBeside(const DetectorConfig& c, const Plane& wall, const CenterLine& l)
      : cfg(c), line(l), across(l.axis.cross(wall.normal)) {}
  int side_of(const Eigen::Vector3f& p) const {
    const Eigen::Vector3f r = p - line.point;
    const float t = r.dot(line.axis);
    if (t < line.t_min_m || t > line.t_max_m) return -1;
    const float u = r.dot(across);
    const float u_abs = std::fabs(u);
    if (u_abs < cfg.mount_beside_min_m || u_abs > cfg.mount_beside_max_m) return -1;
    return u > 0.0f ? 1 : 0;
  }
};

Eigen::Vector3f position(const CloudPoint& q) {
  return Eigen::Vector3f(q.x_m, q.y_m, q.z_m);
}
}  // namespace

MountBeside measure_mount_beside(const OrganizedCloud& cloud, const DetectorConfig& cfg,
                                 const Workspace& ws, const Plane& wall, const CenterLine& line,
                                 float mount_above_wall_m) {
  MountBeside m;
  const BandBeside band(cfg, wall, line);
  const float foot_m = mount_above_wall_m - cfg.mount_step_m;  // a seat track's foot
  for (std::int32_t i : ws.sample) {
    const CloudPoint& q = cloud.points[i];
    const Eigen::Vector3f p = position(q);
    const int side = band.side_of(p);
    if (side < 0) continue;
    ++m.band_pixels[side];
    const float noise = q.noise_m > 0.0f && q.noise_m < 0.05f ? q.noise_m : 0.0f;
    const float tolerance =
        cfg.mount_beside_tolerance_m + std::fmin(2.0f * noise, kMaxNoiseWidening_m);
    const float h = wall.signed_distance(p);
    const float from_level_m = std::fabs(h - mount_above_wall_m);
    const float from_foot_m = std::fabs(h - foot_m);
    if (from_level_m > tolerance && from_foot_m > tolerance) continue;
    // Noise may widen both windows until they overlap: the nearer level
    // takes the pixel.
    ++(from_level_m <= from_foot_m ? m.at_level : m.at_foot)[side];
  }
  return m;
}

bool track_shows_beside(const MountBeside& m, const DetectorConfig& cfg) {
  bool level_runs_on = false, foot_shows = false;
  for (int side = 0; side < 2; ++side) {
    if (m.band_pixels[side] < cfg.track_beside_min_pixels) continue;
    const float needed = cfg.mount_beside_min_fraction * static_cast<float>(m.band_pixels[side]);
    if (static_cast<float>(m.at_level[side]) >= needed && m.at_level[side] > m.at_foot[side]) {
      level_runs_on = true;
    }
    if (static_cast<float>(m.at_foot[side]) >= needed && m.at_foot[side] > m.at_level[side]) {
      foot_shows = true;
    }
  }
  return foot_shows || !level_runs_on;
}

bool open_face_both_sides(const MountBeside& m, const DetectorConfig& cfg) {
  for (int side = 0; side < 2; ++side) {
    if (m.band_pixels[side] < cfg.track_beside_min_pixels) return false;
    const float needed = cfg.mount_beside_min_fraction * static_cast<float>(m.band_pixels[side]);
    if (!(static_cast<float>(m.at_level[side]) >= needed && m.at_level[side] > m.at_foot[side])) {
      return false;
    }
  }
  return true;
}

bool mount_shows_beside(const MountBeside& m, const DetectorConfig& cfg) {
  bool judged = false;
  for (int side = 0; side < 2; ++side) {
    if (m.band_pixels[side] < cfg.mount_beside_min_pixels) continue;
    judged = true;
    if (static_cast<float>(m.at_mount(side)) >=
        cfg.mount_beside_min_fraction * static_cast<float>(m.band_pixels[side])) {
      return true;
    }
  }
  return !judged;
}

LevelsBeside find_levels_beside(const OrganizedCloud& cloud, const DetectorConfig& cfg,
                                const Workspace& ws, const Plane& wall, const CenterLine& line,
                                float lo_m, float hi_m) {
  constexpr int kBins = 32;
  constexpr float kBin_m = 0.0025f;
  constexpr float kRefine_m = 0.005f;
  LevelsBeside out;
  if (!(hi_m > lo_m)) return out;
  const int bins = std::min(kBins, static_cast<int>(std::ceil((hi_m - lo_m) / kBin_m)));
  std::uint32_t hist[2][kBins] = {};
  std::uint32_t band_pixels[2] = {0, 0};
  const BandBeside band(cfg, wall, line);
  // Two passes: the histogram over the sample, then the mean near its peak
  // over the band's heights, kept from the first (side 0's from the front
  // of the buffer, side 1's from its back, each in the sample's order). The
  // sample holds at most kMaxRefitSamples pixels (its capacity).
  constexpr std::size_t kMaxHeights = Workspace::kMaxRefitSamples;
  float height_m[kMaxHeights];
  std::size_t heights[2] = {0, 0};
  for (std::int32_t i : ws.sample) {
    const Eigen::Vector3f p = position(cloud.points[i]);
    const int side = band.side_of(p);
    if (side < 0) continue;
    ++band_pixels[side];
    const float h = wall.signed_distance(p);
    if (heights[0] + heights[1] < kMaxHeights) {
      if (side == 0) {
        height_m[heights[0]++] = h;
      } else {
        height_m[kMaxHeights - 1 - heights[1]++] = h;
      }
    }
    const float x = (h - lo_m) / kBin_m;
    if (!(x >= 0.0f && x < static_cast<float>(bins))) continue;  // NaN too
    ++hist[side][static_cast<int>(x)];
  }
  float peak_m[2] = {0.0f, 0.0f};
  bool have[2] = {false, false};
  for (int side = 0; side < 2; ++side) {
    if (band_pixels[side] < cfg.mount_beside_min_pixels) continue;
    std::uint32_t best = 0;
    int peak = -1;
    for (int b = 0; b < bins; ++b) {
      const std::uint32_t v = hist[side][b] + (b > 0 ? hist[side][b - 1] : 0u) +
                              (b + 1 < bins ? hist[side][b + 1] : 0u);
      if (v > best) {
        best = v;
        peak = b;
      }
    }
    if (peak < 0) continue;
    peak_m[side] = lo_m + (static_cast<float>(peak) + 0.5f) * kBin_m;
    have[side] = true;
  }
  if (!have[0] && !have[1]) return out;
  double sum[2] = {0.0, 0.0};
  std::uint32_t near[2] = {0, 0};
  for (int side = 0; side < 2; ++side) {
    if (!have[side]) continue;
    for (std::size_t k = 0; k < heights[side]; ++k) {
      const float h = height_m[side == 0 ? k : kMaxHeights - 1 - k];
      if (std::fabs(h - peak_m[side]) <= kRefine_m) {
        sum[side] += h;
        ++near[side];
      }
    }
  }
  for (int side = 0; side < 2; ++side) {
    if (!have[side] || near[side] < cfg.mount_beside_min_pixels) continue;
    if (static_cast<float>(near[side]) <
        cfg.mount_beside_min_fraction * static_cast<float>(band_pixels[side])) {
      continue;
    }
    out.level_m[out.count++] = static_cast<float>(sum[side] / near[side]);
  }
  return out;
}

}  // namespace estimator
