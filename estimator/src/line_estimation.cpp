#include "estimator/line_estimation.hpp"

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>

namespace estimator {
namespace {

constexpr float kHalfPi = 1.57079632679f;

// An orthonormal basis of the wall plane: points projected onto the wall
// along its normal become 2-D, and every line test a multiply-add.
struct WallBasis {
  Eigen::Vector3f e1, e2, n;
  float d;
  explicit WallBasis(const Plane& wall) : n(wall.normal), d(wall.d) {
    const Eigen::Vector3f helper =
        std::fabs(n.x()) < 0.9f ? Eigen::Vector3f::UnitX() : Eigen::Vector3f::UnitY();
    e1 = n.cross(helper).normalized();
    e2 = n.cross(e1);
  }
  Eigen::Vector3f to_3d(float u, float v) const { return u * e1 + v * e2 - d * n; }
  Eigen::Vector3f direction_3d(float du, float dv) const { return du * e1 + dv * e2; }
};

// A line in wall coordinates: a point and a unit direction.
struct Line2 {
  float pu, pv, du, dv;
  float distance(float u, float v) const { return std::fabs((u - pu) * dv - (v - pv) * du); }
};

Line2 to_line2(const WallBasis& basis, const LineModel& line) {
  const Eigen::Vector3f dir = line.direction - line.direction.dot(basis.n) * basis.n;
  const float du = dir.dot(basis.e1), dv = dir.dot(basis.e2);
  const float len = std::sqrt(du * du + dv * dv);
  return {line.point.dot(basis.e1), line.point.dot(basis.e2), du / len, dv / len};
}

LineModel to_model(const WallBasis& basis, const Line2& l, std::uint32_t score) {
  const Eigen::Vector3f dir = basis.direction_3d(l.du, l.dv);
  return {true, basis.to_3d(l.pu, l.pv), dir, line_angle_psi(dir), score};
}

}  // namespace

float line_angle_psi(const Eigen::Vector3f& direction) {
  return std::atan2(std::fabs(direction.x()), std::fabs(direction.y()));
}

void project_to_wall(const OrganizedCloud& cloud, const Plane& wall, Workspace& ws) {
  const WallBasis basis(wall);
  for (std::int32_t i : ws.side) {
    const CloudPoint& p = cloud.points[i];
    const Eigen::Vector3f q(p.x_m, p.y_m, p.z_m);
    ws.wall_u_m[i] = q.dot(basis.e1);
    ws.wall_v_m[i] = q.dot(basis.e2);
  }
}

void estimate_handrail_candidates(const OrganizedCloud& cloud, const DetectorConfig& cfg,
                                  const Plane& wall, Random& rng, Workspace& ws,
                                  const IndexList& pts, LineModel candidates[2]) {
  (void)cloud;
  candidates[0] = LineModel{};
  candidates[1] = LineModel{};
  const std::size_t n = pts.size();
  if (n < 2) return;
  const WallBasis basis(wall);
  const float* u = ws.wall_u_m.get();
  const float* v = ws.wall_v_m.get();
  // The scoring subsample, copied into contiguous arrays.
  const std::size_t capacity =
      std::min<std::size_t>(cfg.line_score_samples, Workspace::kMaxScoreSamples);
  const std::size_t step = (n + capacity - 1) / capacity;
  float* score_u = ws.score_x_m.get();
  float* score_v = ws.score_y_m.get();
  std::size_t m = 0;
  for (std::size_t k = 0; k < n; k += step, ++m) {
    score_u[m] = u[pts[k]];
    score_v[m] = v[pts[k]];
  }
  const std::uint32_t n32 = static_cast<std::uint32_t>(n);
  // Two samples closer than this give a poorly defined direction.
  const float min_separation_m = 2.0f * cfg.handrail.bar_width_m;
  float psi[2] = {0.0f, 0.0f};
  Line2 best[2] = {};

  for (std::uint32_t it = 0; it < cfg.line_iterations; ++it) {
    const std::int32_t a = pts[rng.below(n32)], b = pts[rng.below(n32)];
    const float du = u[a] - u[b], dv = v[a] - v[b];
    const float separation = std::sqrt(du * du + dv * dv);
    if (separation < min_separation_m) continue;
    const Line2 line{u[a], v[a], du / separation, dv / separation};
    std::uint32_t score = 0;
    for (std::size_t k = 0; k < m; ++k) {
      score += line.distance(score_u[k], score_v[k]) < cfg.line_inlier_m ? 1u : 0u;
    }
    const float psi_new = line_angle_psi(basis.direction_3d(line.du, line.dv));
    const int slot = std::fabs(psi_new - psi[0]) <= std::fabs(psi_new - psi[1]) ? 0 : 1;
    const int other = 1 - slot;
    if (score > candidates[slot].score) {
      best[slot] = line;
      candidates[slot].score = score;
      candidates[slot].valid = true;
      psi[slot] = psi_new;
      // The weaker slot follows the dominant one at a right angle.
      if (candidates[slot].score > candidates[other].score) psi[other] = kHalfPi - psi[slot];
    }
  }
  for (int k = 0; k < 2; ++k) {
    if (candidates[k].valid) candidates[k] = to_model(basis, best[k], candidates[k].score);
  }
}

void collect_line_inliers(const OrganizedCloud& cloud, const DetectorConfig& cfg, const Plane& wall,
                          const Workspace& ws, const LineModel& line, const IndexList& points,
                          IndexList& out) {
  (void)cloud;
  out.clear();
  if (!line.valid) return;
  const Line2 l = to_line2(WallBasis(wall), line);
  for (std::int32_t i : points) {
    if (l.distance(ws.wall_u_m[i], ws.wall_v_m[i]) < cfg.line_inlier_m) out.push(i);
  }
}

void refine_line(const OrganizedCloud& cloud, const DetectorConfig& cfg, const Plane& wall,
                 const Workspace& ws, const IndexList& points, LineModel* line,
                 IndexList& inliers) {
  const WallBasis basis(wall);
  for (int pass = 0; pass < 2; ++pass) {
    collect_line_inliers(cloud, cfg, wall, ws, *line, points, inliers);
    if (inliers.size() < 3) return;
    // Principal axis of the inliers, in wall coordinates (2 x 2).
    double su = 0, sv = 0;
    for (std::int32_t i : inliers) {
      su += ws.wall_u_m[i];
      sv += ws.wall_v_m[i];
    }
    const double m = static_cast<double>(inliers.size());
    const double mu = su / m, mv = sv / m;
    double cuu = 0, cuv = 0, cvv = 0;
    for (std::int32_t i : inliers) {
      const double a = ws.wall_u_m[i] - mu, b = ws.wall_v_m[i] - mv;
      cuu += a * a;
      cuv += a * b;
      cvv += b * b;
    }
    const double angle = 0.5 * std::atan2(2.0 * cuv, cuu - cvv);
    const Line2 l{static_cast<float>(mu), static_cast<float>(mv),
                  static_cast<float>(std::cos(angle)), static_cast<float>(std::sin(angle))};
    *line = to_model(basis, l, line->score);
  }
  collect_line_inliers(cloud, cfg, wall, ws, *line, points, inliers);
}

void remove_line_points(const Plane& wall, const Workspace& ws, const LineModel& line, float band_m,
                        float max_height_m, IndexList& points) {
  const Line2 l = to_line2(WallBasis(wall), line);
  std::size_t kept = 0;
  for (std::size_t k = 0; k < points.size(); ++k) {
    const std::int32_t i = points[k];
    const bool drop = l.distance(ws.wall_u_m[i], ws.wall_v_m[i]) < band_m &&
                      ws.signed_distance_m[i] <= max_height_m;
    if (!drop) points[kept++] = i;
  }
  points.resize_down(kept);
}

Cluster cluster_along_line(const OrganizedCloud& cloud, const DetectorConfig& cfg,
                           const LineModel& line, IndexList& inliers, float* t_m) {
  Cluster best;
  if (inliers.empty()) return best;
  const float dx = line.direction.x(), dy = line.direction.y(), dz = line.direction.z();
  const float t0 = line.point.dot(line.direction);
  float t_lo = INFINITY, t_hi = -INFINITY;
  for (std::int32_t i : inliers) {
    const CloudPoint& p = cloud.points[i];
    const float t = dx * p.x_m + dy * p.y_m + dz * p.z_m - t0;
    t_m[i] = t;
    t_lo = t < t_lo ? t : t_lo;
    t_hi = t > t_hi ? t : t_hi;
  }
  // No sort: bins no wider than d_r, each keeping its count and its
  // smallest and largest t. Points sharing a bin are closer than d_r, and
  // the gap between two occupied bins with nothing between them is exactly
  // the next bin's smallest t minus this bin's largest, so the runs are
  // those of a sorted walk. (Past kBins * d_r of line the bins widen.)
  constexpr int kBins = 512;
  const float bin_m = std::fmax(cfg.cluster_gap_m, (t_hi - t_lo) / (kBins - 1));
  std::uint32_t count[kBins] = {};
  float bin_min[kBins], bin_max[kBins];
  const int used = std::min(static_cast<int>((t_hi - t_lo) / bin_m) + 1, kBins);
  for (std::int32_t i : inliers) {
    const int b = std::min(static_cast<int>((t_m[i] - t_lo) / bin_m), used - 1);
    if (count[b] == 0) {
      bin_min[b] = bin_max[b] = t_m[i];
    } else {
      bin_min[b] = std::fmin(bin_min[b], t_m[i]);
      bin_max[b] = std::fmax(bin_max[b], t_m[i]);
    }
    ++count[b];
  }
  std::uint32_t run_count = 0, best_count = 0;
  float run_min = 0.0f, last_max = 0.0f;
  for (int b = 0; b < used; ++b) {
    if (count[b] == 0) continue;
    if (run_count > 0 && bin_min[b] - last_max > cfg.cluster_gap_m) run_count = 0;
    if (run_count == 0) run_min = bin_min[b];
    run_count += count[b];
    last_max = bin_max[b];
    if (run_count > best_count) {
      best_count = run_count;
      best.t_min_m = run_min;
      best.t_max_m = last_max;
    }
  }
  // Keep the winning run's points, in their order.
  std::size_t kept = 0;
  for (std::size_t k = 0; k < inliers.size(); ++k) {
    const float t = t_m[inliers[k]];
    if (t >= best.t_min_m && t <= best.t_max_m) inliers[kept++] = inliers[k];
  }
  inliers.resize_down(kept);
  best.count = static_cast<std::uint32_t>(kept);
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
