#include "estimator/local_surface.hpp"

#include <Eigen/Eigenvalues>
#include <cmath>

#include "estimator/moments.hpp"

namespace estimator {
namespace {

constexpr float kTubeInnerM = 0.035f;  // clear of the bar's faces (within 2 cm of its line)
constexpr float kTubeOuterM = 0.13f;
constexpr float kInlierM = 0.01f;
constexpr float kHeightSpareM = 0.015f;
constexpr std::uint32_t kTriples = 48;
constexpr std::uint32_t kMinInliers = 16;
constexpr std::size_t kMaxAround = 1024;

Eigen::Vector3f position(const CloudPoint& q) {
  return Eigen::Vector3f(q.x_m, q.y_m, q.z_m);
}

// The plane through three points, its normal toward the camera (the
// origin); false when they are nearly collinear.
bool plane_through(const Eigen::Vector3f& a, const Eigen::Vector3f& b, const Eigen::Vector3f& c,
                   Plane* out) {
  Eigen::Vector3f n = (b - a).cross(c - a);
  const float norm = n.norm();
  if (!(norm > 1e-6f)) return false;
  n /= norm;
  if (n.dot(a) > 0.0f) n = -n;
  out->normal = n;
  out->d = -n.dot(a);
  return true;
}

}  // namespace

LocalSurface fit_surface_around_bar(const OrganizedCloud& cloud, const DetectorConfig& cfg,
                                    const Workspace& ws, const IndexList& inliers,
                                    const Eigen::Vector3f& axis, Random& rng) {
  LocalSurface out;
  if (inliers.size() < 3) return out;
  // The bar's line: through its pixels' centroid along the axis.
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (std::int32_t i : inliers) sum += position(cloud.points[i]).cast<double>();
  const Eigen::Vector3f centre = (sum / static_cast<double>(inliers.size())).cast<float>();
  float t_min = INFINITY, t_max = -INFINITY;
  for (std::int32_t i : inliers) {
    const float t = (position(cloud.points[i]) - centre).dot(axis);
    t_min = std::fmin(t_min, t);
    t_max = std::fmax(t_max, t);
  }
  std::int32_t around[kMaxAround];
  std::size_t n = 0;
  for (std::int32_t i : ws.sample) {
    if (n >= kMaxAround) break;
    const Eigen::Vector3f r = position(cloud.points[i]) - centre;
    const float t = r.dot(axis);
    if (t < t_min || t > t_max) continue;
    const float d = (r - t * axis).norm();
    if (d < kTubeInnerM || d > kTubeOuterM) continue;
    around[n++] = i;
  }
  if (n < kMinInliers) return out;
  const auto count_inliers = [&](const Plane& p) {
    std::uint32_t c = 0;
    for (std::size_t k = 0; k < n; ++k) {
      c += std::fabs(p.signed_distance(position(cloud.points[around[k]]))) <= kInlierM;
    }
    return c;
  };
  // The surface under the bar stands a handrail's front height behind the
  // bar's pixels (most of them its front face); a wall beside it does not.
  const float height_lo = bar_front_min_m(cfg.handrail) - kHeightSpareM;
  const float height_hi = bar_front_max_m(cfg.handrail) + kHeightSpareM;
  Plane best;
  std::uint32_t best_inliers = 0;
  for (std::uint32_t k = 0; k < kTriples; ++k) {
    const auto pick = [&]() {
      return position(cloud.points[around[rng.below(static_cast<std::uint32_t>(n))]]);
    };
    Plane p;
    if (!plane_through(pick(), pick(), pick(), &p)) continue;
    const float h = p.signed_distance(centre);
    if (h < height_lo || h > height_hi) continue;
    const std::uint32_t c = count_inliers(p);
    if (c > best_inliers) {
      best_inliers = c;
      best = p;
    }
  }
  if (best_inliers < kMinInliers || 5 * best_inliers < 2 * n) return out;
  // Least squares over the inliers: the normal is the direction of least
  // spread.
  PointMoments m;
  m.set_reference(centre.x(), centre.y(), centre.z());
  for (std::size_t k = 0; k < n; ++k) {
    const Eigen::Vector3f q = position(cloud.points[around[k]]);
    if (std::fabs(best.signed_distance(q)) <= kInlierM) m.add(q.x(), q.y(), q.z());
  }
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver;
  solver.computeDirect(m.covariance());
  Eigen::Vector3f normal = solver.eigenvectors().col(0).cast<float>();
  if (!normal.allFinite()) return out;
  const Eigen::Vector3f on_plane = m.mean().cast<float>();
  if (normal.dot(on_plane) > 0.0f) normal = -normal;
  out.plane.normal = normal;
  out.plane.d = -normal.dot(on_plane);
  out.inliers = static_cast<std::uint32_t>(m.n);
  out.front_height_m = out.plane.signed_distance(centre);
  out.found = out.front_height_m >= height_lo && out.front_height_m <= height_hi;
  return out;
}

void distances_to_plane(const OrganizedCloud& cloud, const Plane& plane,
                        const float* valid_distance_m, float* distance_m) {
  const std::size_t n = cloud.size();
  for (std::size_t i = 0; i < n; ++i) {
    distance_m[i] = std::isfinite(valid_distance_m[i])
                        ? plane.signed_distance(position(cloud.points[i]))
                        : -INFINITY;
  }
}

void raised_over_surface(const OrganizedCloud& cloud, const DetectorConfig& cfg,
                         const Workspace& ws, IndexList& out) {
  const float lo = bar_front_min_m(cfg.handrail) - cfg.handrail.bar_depth_m - cfg.gap_margin_m;
  const float hi = bar_front_max_m(cfg.handrail) + cfg.gap_margin_m;
  const float* distance_m = ws.signed_distance_m.get();
  const float* widen_m = ws.gap_widen_m.get();
  out.clear();
  const std::size_t n = cloud.size();
  for (std::size_t i = 0; i < n; ++i) {
    const float s = distance_m[i];
    if (s >= lo - widen_m[i] && s <= hi + widen_m[i]) out.push(static_cast<std::int32_t>(i));
  }
}

float tilt_between_deg(const Plane& a, const Plane& b) {
  const float c = std::fmin(1.0f, std::fabs(a.normal.dot(b.normal)));
  return std::acos(c) * 57.2957795f;
}

}  // namespace estimator
