// The paper's "basic algorithm", kept for comparison: the wall by RANSAC,
// then one line by RANSAC through everything in front of the wall. No
// handrail-shape tests, no clustering, no end detection.
#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <cmath>

#include "estimator/handrail_detector.hpp"
#include "estimator/handrail_filters.hpp"
#include "estimator/handrail_pose.hpp"
#include "estimator/plane_estimation.hpp"

namespace estimator {
namespace {
Eigen::Vector3f point_of(const OrganizedCloud& cloud, std::int32_t i) {
  const CloudPoint& p = cloud.points[i];
  return {p.x_m, p.y_m, p.z_m};
}
}  // namespace

void HandrailDetector::run_basic(const OrganizedCloud& cloud, HandrailDetection* out) {
  const PlaneEstimate plane = estimate_plane(cloud, cfg_, rng_, ws_);
  if (!plane.found) {
    clear_flags(cloud);
    out->status = DetectStatus::kNoPlane;
    return;
  }
  wall_ = plane.plane;
  // Per-pixel distances to the wall (the gap set itself is not used here).
  out->counts.plane_inliers = gap_distance_test(cloud, cfg_, wall_, ws_, &out->counts.valid);

  // Plane outliers in front of the wall (not behind it, not the far room).
  IndexList& outliers = ws_.gap;
  outliers.clear();
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    if (!(ws_.flags[i] & kFlagValid)) continue;
    const float s = ws_.signed_distance_m[i];
    if (s > 2.0f * cfg_.plane_inlier_m && s < 0.3f) outliers.push(static_cast<std::int32_t>(i));
  }
  out->counts.gap = static_cast<std::uint32_t>(outliers.size());
  const std::size_t n = outliers.size();
  if (n < cfg_.min_line_inliers) {
    out->status = DetectStatus::kNoCandidates;
    return;
  }
  const std::size_t step = n > cfg_.line_score_samples ? n / cfg_.line_score_samples : 1;
  Eigen::Vector3f best_point = Eigen::Vector3f::Zero(), best_dir = Eigen::Vector3f::Zero();
  std::uint32_t best_score = 0;
  for (std::uint32_t it = 0; it < cfg_.line_iterations; ++it) {
    const Eigen::Vector3f p1 = point_of(cloud, outliers[rng_.below(static_cast<std::uint32_t>(n))]);
    const Eigen::Vector3f p2 = point_of(cloud, outliers[rng_.below(static_cast<std::uint32_t>(n))]);
    const float separation = (p1 - p2).norm();
    if (separation < 0.02f) continue;
    const Eigen::Vector3f dir = (p1 - p2) / separation;
    std::uint32_t score = 0;
    for (std::size_t k = 0; k < n; k += step) {
      score += (point_of(cloud, outliers[k]) - p1).cross(dir).norm() < cfg_.line_inlier_m;
    }
    if (score > best_score) {
      best_score = score;
      best_point = p1;
      best_dir = dir;
    }
  }
  IndexList& inliers = ws_.line[0];
  inliers.clear();
  if (best_score > 0) {
    for (std::int32_t i : outliers) {
      if ((point_of(cloud, i) - best_point).cross(best_dir).norm() < cfg_.line_inlier_m) {
        inliers.push(i);
      }
    }
  }
  if (inliers.size() < cfg_.min_line_inliers) {
    out->status = DetectStatus::kNoLine;
    return;
  }
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (std::int32_t i : inliers) mean += point_of(cloud, i).cast<double>();
  mean /= static_cast<double>(inliers.size());
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (std::int32_t i : inliers) {
    const Eigen::Vector3d q = point_of(cloud, i).cast<double>() - mean;
    cov.noalias() += q * q.transpose();
  }
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver;
  solver.computeDirect(cov);
  const Eigen::Matrix3f R =
      handrail_frame(wall_.normal, solver.eigenvectors().col(2).cast<float>());
  const Eigen::Vector3f center = mean.cast<float>();
  float t_min = 0.0f, t_max = 0.0f;
  for (std::int32_t i : inliers) {
    const float t = (point_of(cloud, i) - center).dot(R.col(2));
    t_min = std::fmin(t_min, t);
    t_max = std::fmax(t_max, t);
    ws_.flags[i] |= kFlagLine;
  }
  out->counts.line = static_cast<std::uint32_t>(inliers.size());
  out->inliers = out->counts.line;
  out->state = HandrailState::kNoEnd;
  out->ends_cam[0] = center + t_min * R.col(2);
  out->ends_cam[1] = center + t_max * R.col(2);
  out->visible_length_m = t_max - t_min;
  out->beam_length_m = out->visible_length_m;
  fill_pose(center, R, out);
}

}  // namespace estimator
