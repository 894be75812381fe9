#include "estimator/plane_estimation.hpp"

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <cmath>

namespace estimator {
namespace {

Eigen::Vector3f point_of(const OrganizedCloud& cloud, std::int32_t i) {
  const CloudPoint& p = cloud.points[i];
  return {p.x_m, p.y_m, p.z_m};
}

bool plane_from_triple(const Eigen::Vector3f& a, const Eigen::Vector3f& b, const Eigen::Vector3f& c,
                       Plane* plane) {
  Eigen::Vector3f n = (b - a).cross(c - a);
  const float norm = n.norm();
  // Near-collinear triples give no plane; 1 cm^2 of spanned area at least.
  if (norm < 1e-4f) return false;
  n /= norm;
  plane->normal = n;
  plane->d = -n.dot(a);
  return true;
}

// The valid pixels within the distance of the plane, into out, taking
// every step-th: a few thousand points fix a plane far better than the
// noise, and the refits need no more.
void gather_inliers(const OrganizedCloud& cloud, const IndexList& valid, const Plane& plane,
                    float max_distance_m, std::size_t step, IndexList& out) {
  out.clear();
  for (std::size_t k = 0; k < valid.size(); k += step) {
    const std::int32_t i = valid[k];
    if (std::fabs(plane.signed_distance(point_of(cloud, i))) < max_distance_m) out.push(i);
  }
}

constexpr std::size_t kRefitPoints = 6000;
std::size_t step_for(std::size_t n) {
  return n > kRefitPoints ? n / kRefitPoints : 1;
}

}  // namespace

bool fit_plane_least_squares(const OrganizedCloud& cloud, const std::int32_t* indices,
                             std::size_t count, Plane* plane) {
  if (count < 3) return false;
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (std::size_t k = 0; k < count; ++k) mean += point_of(cloud, indices[k]).cast<double>();
  mean /= static_cast<double>(count);
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (std::size_t k = 0; k < count; ++k) {
    const Eigen::Vector3d q = point_of(cloud, indices[k]).cast<double>() - mean;
    cov.noalias() += q * q.transpose();
  }
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver;
  solver.computeDirect(cov);
  Eigen::Vector3d n = solver.eigenvectors().col(0);
  if (!n.allFinite() || n.norm() < 0.5) return false;
  n.normalize();
  double d = -n.dot(mean);
  // Keep the camera (the origin) on the positive side.
  if (d < 0.0) {
    n = -n;
    d = -d;
  }
  plane->normal = n.cast<float>();
  plane->d = static_cast<float>(d);
  return true;
}

PlaneEstimate estimate_plane(const OrganizedCloud& cloud, const DetectorConfig& cfg, Random& rng,
                             Workspace& ws) {
  PlaneEstimate result;
  const IndexList& valid = ws.valid;
  const std::size_t n = valid.size();
  if (n < 3) return result;
  const std::size_t step = n > cfg.plane_score_samples ? n / cfg.plane_score_samples : 1;
  const std::uint32_t n_valid = static_cast<std::uint32_t>(n);

  Plane best;
  std::uint32_t best_score = 0, scored = 0;
  for (std::uint32_t it = 0; it < cfg.plane_iterations; ++it) {
    Plane hypothesis;
    if (!plane_from_triple(point_of(cloud, valid[rng.below(n_valid)]),
                           point_of(cloud, valid[rng.below(n_valid)]),
                           point_of(cloud, valid[rng.below(n_valid)]), &hypothesis)) {
      continue;
    }
    std::uint32_t score = 0, total = 0;
    for (std::size_t k = 0; k < n; k += step, ++total) {
      score +=
          std::fabs(hypothesis.signed_distance(point_of(cloud, valid[k]))) < cfg.plane_inlier_m;
    }
    if (score > best_score) {
      best_score = score;
      best = hypothesis;
    }
    scored = total;
  }
  if (scored == 0 || best_score < cfg.plane_min_inlier_fraction * static_cast<float>(scored)) {
    return result;
  }

  // Two refits: the second one sees inliers of a plane no longer tilted by
  // the triple's noise.
  for (int pass = 0; pass < 2; ++pass) {
    gather_inliers(cloud, valid, best, cfg.plane_inlier_m, step_for(n), ws.scratch);
    if (!fit_plane_least_squares(cloud, ws.scratch.begin(), ws.scratch.size(), &best)) {
      return result;
    }
  }
  if (best.d < 0.0f) return result;

  // Support, judged on the last refit's subsample: the per-pixel distances
  // are written by the gap distance test, in its single pass over the frame.
  const std::size_t sampled = (n + step_for(n) - 1) / step_for(n);
  const float support = static_cast<float>(ws.scratch.size()) / static_cast<float>(sampled);
  if (support < cfg.plane_min_inlier_fraction) return result;
  const std::uint32_t inliers = static_cast<std::uint32_t>(support * static_cast<float>(n));
  result.found = true;
  result.plane = best;
  result.inliers = inliers;
  return result;
}

}  // namespace estimator
