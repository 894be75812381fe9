#include "estimator/line_estimation.hpp"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>

namespace estimator {
namespace {

constexpr float kHalfPi = 1.57079632679f;

// The point moved onto the wall along the normal: depth noise along the view
// ray then no longer scatters points across the line.
Eigen::Vector3f on_wall(const OrganizedCloud& cloud, const Plane& wall, std::int32_t i) {
  const CloudPoint& p = cloud.points[i];
  const Eigen::Vector3f q(p.x_m, p.y_m, p.z_m);
  return q - wall.signed_distance(q) * wall.normal;
}

float distance_to_line(const Eigen::Vector3f& q, const Eigen::Vector3f& point,
                       const Eigen::Vector3f& direction) {
  return (q - point).cross(direction).norm();
}

}  // namespace

float line_angle_psi(const Eigen::Vector3f& direction) {
  return std::atan2(std::fabs(direction.x()), std::fabs(direction.y()));
}

void estimate_handrail_candidates(const OrganizedCloud& cloud, const DetectorConfig& cfg,
                                  const Plane& wall, Random& rng, const IndexList& pts,
                                  LineModel candidates[2]) {
  candidates[0] = LineModel{};
  candidates[1] = LineModel{};
  const std::size_t n = pts.size();
  if (n < 2) return;
  const std::size_t step = n > cfg.line_score_samples ? n / cfg.line_score_samples : 1;
  const std::uint32_t n32 = static_cast<std::uint32_t>(n);
  // Two samples closer than this give a poorly defined direction.
  const float min_separation_m = 2.0f * cfg.handrail.bar_width_m;
  float psi[2] = {0.0f, 0.0f};

  for (std::uint32_t it = 0; it < cfg.line_iterations; ++it) {
    const Eigen::Vector3f p1 = on_wall(cloud, wall, pts[rng.below(n32)]);
    const Eigen::Vector3f p2 = on_wall(cloud, wall, pts[rng.below(n32)]);
    const Eigen::Vector3f delta = p1 - p2;
    const float separation = delta.norm();
    if (separation < min_separation_m) continue;
    const Eigen::Vector3f beta = delta / separation;
    std::uint32_t score = 0;
    for (std::size_t k = 0; k < n; k += step) {
      score += distance_to_line(on_wall(cloud, wall, pts[k]), p1, beta) < cfg.line_inlier_m;
    }
    const float psi_new = line_angle_psi(beta);
    const int slot = std::fabs(psi_new - psi[0]) <= std::fabs(psi_new - psi[1]) ? 0 : 1;
    const int other = 1 - slot;
    if (score > candidates[slot].score) {
      candidates[slot] = {true, p1, beta, psi_new, score};
      psi[slot] = psi_new;
      // The weaker slot follows the dominant one at a right angle.
      if (candidates[slot].score > candidates[other].score) psi[other] = kHalfPi - psi[slot];
    }
  }
}

void collect_line_inliers(const OrganizedCloud& cloud, const DetectorConfig& cfg, const Plane& wall,
                          const LineModel& line, const IndexList& points, IndexList& out) {
  out.clear();
  if (!line.valid) return;
  for (std::int32_t i : points) {
    if (distance_to_line(on_wall(cloud, wall, i), line.point, line.direction) < cfg.line_inlier_m) {
      out.push(i);
    }
  }
}

void remove_line_points(const OrganizedCloud& cloud, const DetectorConfig& cfg, const Plane& wall,
                        const LineModel& line, IndexList& points) {
  std::size_t kept = 0;
  for (std::size_t k = 0; k < points.size(); ++k) {
    const std::int32_t i = points[k];
    if (distance_to_line(on_wall(cloud, wall, i), line.point, line.direction) >=
        cfg.line_inlier_m) {
      points[kept++] = i;
    }
  }
  points.resize_down(kept);
}

Cluster cluster_along_line(const OrganizedCloud& cloud, const DetectorConfig& cfg,
                           const LineModel& line, IndexList& inliers, float* t_m) {
  Cluster best;
  if (inliers.empty()) return best;
  for (std::int32_t i : inliers) {
    const CloudPoint& p = cloud.points[i];
    t_m[i] = (Eigen::Vector3f(p.x_m, p.y_m, p.z_m) - line.point).dot(line.direction);
  }
  std::sort(inliers.begin(), inliers.end(),
            [t_m](std::int32_t a, std::int32_t b) { return t_m[a] < t_m[b]; });
  std::size_t run_start = 0, best_start = 0, best_count = 0;
  for (std::size_t k = 1; k <= inliers.size(); ++k) {
    const bool split =
        k == inliers.size() || t_m[inliers[k]] - t_m[inliers[k - 1]] > cfg.cluster_gap_m;
    if (!split) continue;
    if (k - run_start > best_count) {
      best_count = k - run_start;
      best_start = run_start;
    }
    run_start = k;
  }
  // Move the winning run to the front and drop the rest.
  std::copy(inliers.begin() + best_start, inliers.begin() + best_start + best_count,
            inliers.begin());
  inliers.resize_down(best_count);
  best.count = static_cast<std::uint32_t>(best_count);
  best.t_min_m = t_m[inliers[0]];
  best.t_max_m = t_m[inliers[best_count - 1]];
  return best;
}

bool bar_front_height_test(const DetectorConfig& cfg, const Workspace& ws, const IndexList& inliers,
                           float* front_m) {
  // Histogram of the inliers' distance from the wall, 2 mm bins, lightly
  // smoothed. The bar's front face (flat on the ISS bar, the crown of a
  // round one) is the densest height; a side face seen at an angle spreads
  // thinly over the bar's depth and does not move the peak.
  constexpr int kBins = 64;
  constexpr float kBin_m = 0.002f;
  const float expected = cfg.handrail.bar_center_offset_m + 0.5f * cfg.handrail.bar_depth_m;
  const float base = expected - 0.5f * kBins * kBin_m;
  float hist[kBins] = {};
  for (std::int32_t i : inliers) {
    const int b = static_cast<int>((ws.signed_distance_m[i] - base) / kBin_m);
    if (b >= 0 && b < kBins) hist[b] += 1.0f;
  }
  float best = -1.0f;
  int peak = 0;
  for (int b = 2; b < kBins - 2; ++b) {
    const float v =
        hist[b - 2] + 2.0f * hist[b - 1] + 3.0f * hist[b] + 2.0f * hist[b + 1] + hist[b + 2];
    if (v > best) {
      best = v;
      peak = b;
    }
  }
  *front_m = base + (static_cast<float>(peak) + 0.5f) * kBin_m;
  return best > 0.0f && std::fabs(*front_m - expected) < cfg.front_height_tolerance_m;
}

int select_by_gripper_angle(const DetectorConfig& cfg, const LineModel candidates[2],
                            const bool usable[2]) {
  int chosen = -1;
  float best = 0.0f;
  for (int k = 0; k < 2; ++k) {
    if (!usable[k]) continue;
    const float diff = std::fabs(cfg.gripper_angle_rad - candidates[k].psi_rad);
    if (chosen < 0 || diff < best) {
      chosen = k;
      best = diff;
    }
  }
  return chosen;
}

}  // namespace estimator
