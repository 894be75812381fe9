#include "estimator/handrail_pose.hpp"

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

namespace estimator {
namespace {

constexpr float kSliceLength_m = 0.02f;
constexpr int kMaxSlices = 160;  // 3.2 m of bar; longer bars share the end slices

Eigen::Vector3f point_of(const OrganizedCloud& cloud, std::int32_t i) {
  const CloudPoint& p = cloud.points[i];
  return {p.x_m, p.y_m, p.z_m};
}

}  // namespace

Eigen::Matrix3f handrail_frame(const Eigen::Vector3f& wall_normal,
                               const Eigen::Vector3f& line_direction) {
  const Eigen::Vector3f u_x = wall_normal.normalized();
  Eigen::Vector3f u_z = line_direction - line_direction.dot(u_x) * u_x;
  u_z.normalize();
  const bool nearer_vertical = std::fabs(u_z.y()) >= std::fabs(u_z.x());
  if ((nearer_vertical && u_z.y() > 0.0f) || (!nearer_vertical && u_z.x() < 0.0f)) u_z = -u_z;
  const Eigen::Vector3f u_y = u_z.cross(u_x);
  Eigen::Matrix3f R;
  R.col(0) = u_x;
  R.col(1) = u_y;
  R.col(2) = u_z;
  return R;
}

bool estimate_center_line(const OrganizedCloud& cloud, const DetectorConfig& cfg, const Plane& wall,
                          const IndexList& inliers, const IndexList& silhouette, CenterLine* line) {
  const std::size_t n = inliers.size();
  if (n < 3) return false;
  const Eigen::Vector3f& normal = wall.normal;

  // Direction: principal axis of the points projected onto the wall.
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (std::int32_t i : inliers) {
    const Eigen::Vector3f p = point_of(cloud, i);
    mean += (p - wall.signed_distance(p) * normal).cast<double>();
  }
  mean /= static_cast<double>(n);
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (std::int32_t i : inliers) {
    const Eigen::Vector3f p = point_of(cloud, i);
    const Eigen::Vector3d q = (p - wall.signed_distance(p) * normal).cast<double>() - mean;
    cov.noalias() += q * q.transpose();
  }
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver;
  solver.computeDirect(cov);
  const Eigen::Vector3f direction = solver.eigenvectors().col(2).cast<float>();
  if (!direction.allFinite()) return false;
  const Eigen::Matrix3f R = handrail_frame(normal, direction);
  const Eigen::Vector3f axis = R.col(2);
  const Eigen::Vector3f across = R.col(1);
  const Eigen::Vector3f origin = mean.cast<float>();

  // Across the bar: midpoint of its silhouette in each 2 cm slice along
  // it. The silhouette is taken from every raised pixel near the line (the
  // gap set), not only from those that passed the cross and side tests: a
  // cable beside the bar can fail one side's probes for a whole edge row,
  // which would pull a midpoint of the inliers alone toward the other side.
  float t_min = 0.0f, t_max = 0.0f;
  for (std::size_t k = 0; k < n; ++k) {
    const float t = (point_of(cloud, inliers[k]) - origin).dot(axis);
    t_min = k == 0 ? t : std::fmin(t_min, t);
    t_max = k == 0 ? t : std::fmax(t_max, t);
  }
  const float half_reach = 0.5f * cfg.handrail.bar_width_m + cfg.line_inlier_m;
  float lo[kMaxSlices], hi[kMaxSlices], mids[kMaxSlices];
  std::uint16_t count[kMaxSlices] = {};
  for (std::int32_t i : silhouette) {
    const Eigen::Vector3f p = point_of(cloud, i);
    const Eigen::Vector3f q = p - wall.signed_distance(p) * normal - origin;
    const float t = q.dot(axis);
    const float b = q.dot(across);
    if (t < t_min || t > t_max || std::fabs(b) > half_reach) continue;
    int slice = static_cast<int>((t - t_min) / kSliceLength_m);
    slice = std::clamp(slice, 0, kMaxSlices - 1);
    lo[slice] = count[slice] ? std::fmin(lo[slice], b) : b;
    hi[slice] = count[slice] ? std::fmax(hi[slice], b) : b;
    if (count[slice] < 0xFFFF) ++count[slice];
  }
  int n_mids = 0;
  for (int s = 0; s < kMaxSlices; ++s) {
    if (count[s] >= 3) mids[n_mids++] = 0.5f * (lo[s] + hi[s]);
  }
  float offset_across = 0.0f;
  if (n_mids > 0) {
    std::nth_element(mids, mids + n_mids / 2, mids + n_mids);
    offset_across = mids[n_mids / 2];
  }

  line->axis = axis;
  line->point = origin + offset_across * across + cfg.handrail.bar_center_offset_m * normal;
  line->t_min_m = t_min;
  line->t_max_m = t_max;
  return true;
}

void detect_ends(const OrganizedCloud& cloud, const DetectorConfig& cfg, const PixelScale& scale,
                 const Workspace& ws, const IndexList& inliers, const CenterLine& line,
                 bool end_seen[2], float end_t_m[2]) {
  end_seen[0] = end_seen[1] = false;
  end_t_m[0] = line.t_min_m;
  end_t_m[1] = line.t_max_m;
  if (inliers.size() < 2 || !scale.ok) return;
  const int w = static_cast<int>(cloud.width);

  // The bar's direction in the image, from the inliers' pixel coordinates.
  double su = 0, sv = 0;
  for (std::int32_t i : inliers) {
    su += i % w;
    sv += i / w;
  }
  const double n = static_cast<double>(inliers.size());
  const double mu = su / n, mv = sv / n;
  double cuu = 0, cuv = 0, cvv = 0;
  for (std::int32_t i : inliers) {
    const double du = i % w - mu, dv = i / w - mv;
    cuu += du * du;
    cuv += du * dv;
    cvv += dv * dv;
  }
  const double angle = 0.5 * std::atan2(2.0 * cuv, cuu - cvv);
  Eigen::Vector2f dir_px(static_cast<float>(std::cos(angle)), static_cast<float>(std::sin(angle)));

  const float lo = gap_min_m(cfg), hi = gap_max_m(cfg);
  for (int end = 0; end < 2; ++end) {
    // Start at the mean pixel of the inliers within 2 cm of this end.
    const float t_end = end == 0 ? line.t_min_m : line.t_max_m;
    double ru = 0, rv = 0, rz = 0;
    int m = 0;
    float t_inner = t_end;
    for (std::int32_t i : inliers) {
      const float t = (point_of(cloud, i) - line.point).dot(line.axis);
      if (std::fabs(t - t_end) < 0.02f) {
        ru += i % w;
        rv += i / w;
        rz += cloud.points[i].z_m;
        ++m;
        t_inner = end == 0 ? std::fmin(t_inner, t) : std::fmax(t_inner, t);
      }
    }
    if (m == 0) continue;
    Eigen::Vector2f start(static_cast<float>(ru / m), static_cast<float>(rv / m));
    // Point the image direction outward: toward this end along the bar.
    Eigen::Vector2f outward =
        start - Eigen::Vector2f(static_cast<float>(mu), static_cast<float>(mv));
    Eigen::Vector2f step = dir_px;
    if (outward.dot(step) < 0.0f) step = -step;
    const float z = static_cast<float>(rz / m);
    const int max_steps =
        std::min(400, static_cast<int>(std::ceil(std::fmax(scale.px_x(cfg.end_search_m, z),
                                                           scale.px_y(cfg.end_search_m, z)))));
    int invalid_run = 0;
    float t_bar = t_inner;
    for (int k = 1; k <= max_steps; ++k) {
      const int col = static_cast<int>(std::lround(start.x() + step.x() * k));
      const int row = static_cast<int>(std::lround(start.y() + step.y() * k));
      if (col < 0 || row < 0 || col >= w || row >= static_cast<int>(cloud.height)) break;
      const std::int32_t i = row * w + col;
      if (!(ws.flags[i] & kFlagValid)) {
        if (++invalid_run > 3) break;
        continue;
      }
      invalid_run = 0;
      const float s = ws.signed_distance_m[i];
      if (s < cfg.wall_tolerance_m) {
        end_seen[end] = true;
        break;
      }
      if (s > hi + 0.02f) break;  // something in front hides the end
      if (s >= lo) {
        const float t = (point_of(cloud, i) - line.point).dot(line.axis);
        t_bar = end == 0 ? std::fmin(t_bar, t) : std::fmax(t_bar, t);
      }
    }
    end_t_m[end] = t_bar;
  }
}

HandrailState handrail_state(const bool end_seen[2]) {
  const int n = (end_seen[0] ? 1 : 0) + (end_seen[1] ? 1 : 0);
  return n == 2   ? HandrailState::kBothEnds
         : n == 1 ? HandrailState::kOneEnd
                  : HandrailState::kNoEnd;
}

void target_pose(const DetectorConfig& cfg, const Eigen::Vector3f& p_cam_center,
                 const Eigen::Matrix3f& R_cam_handrail, Eigen::Vector3f* p_cam_target,
                 Eigen::Matrix3f* R_cam_target) {
  *p_cam_target = p_cam_center + cfg.target_standoff_m * R_cam_handrail.col(0);
  *R_cam_target = R_cam_handrail;
}

}  // namespace estimator
