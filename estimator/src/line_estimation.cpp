#include "estimator/line_estimation.hpp"

#include <Eigen/Eigenvalues>
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

void refine_line(const OrganizedCloud& cloud, const DetectorConfig& cfg, const Plane& wall,
                 const IndexList& points, LineModel* line, IndexList& inliers) {
  for (int pass = 0; pass < 2; ++pass) {
    collect_line_inliers(cloud, cfg, wall, *line, points, inliers);
    if (inliers.size() < 3) return;
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    for (std::int32_t i : inliers) mean += on_wall(cloud, wall, i).cast<double>();
    mean /= static_cast<double>(inliers.size());
    Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
    for (std::int32_t i : inliers) {
      const Eigen::Vector3d q = on_wall(cloud, wall, i).cast<double>() - mean;
      cov.noalias() += q * q.transpose();
    }
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver;
    solver.computeDirect(cov);
    const Eigen::Vector3f direction = solver.eigenvectors().col(2).cast<float>();
    if (!direction.allFinite()) return;
    line->point = mean.cast<float>();
    line->direction = direction.normalized();
    line->psi_rad = line_angle_psi(line->direction);
  }
  collect_line_inliers(cloud, cfg, wall, *line, points, inliers);
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
