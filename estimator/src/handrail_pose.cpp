#include "estimator/handrail_pose.hpp"

#include "estimator/moments.hpp"
#include "four_lanes.hpp"

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

namespace estimator {
namespace {

// A point's coordinate along unit direction e after projecting it onto the
// wall, relative to an origin on the wall: (p - s n - o) . e for wall
// distance s, folded into four constants.
struct LinearForm {
  float ex, ey, ez, en, e0;
  LinearForm(const Eigen::Vector3f& e, const Eigen::Vector3f& n, const Eigen::Vector3f& o)
      : ex(e.x()), ey(e.y()), ez(e.z()), en(e.dot(n)), e0(e.dot(o)) {}
  float operator()(const CloudPoint& p, float s) const {
    return ex * p.x_m + ey * p.y_m + ez * p.z_m - s * en - e0;
  }
};

// Smallest and largest coordinate of the points along `axis` from `origin`.
// With `distance_m`, only of the points at least `min_height_m` over the
// surface (the bar's own pixels: an inlier lower than the bar's back is
// the surface beside or beyond it, which a line seen at a slant collects
// in its 2-D neighbourhood, and it says nothing about where the bar ends);
// then t_min and t_max stay as they are when no point is that high.
void inlier_extent(const OrganizedCloud& cloud, const IndexList& inliers,
                   const Eigen::Vector3f& origin, const Eigen::Vector3f& axis, float* t_min,
                   float* t_max, const float* distance_m = nullptr, float min_height_m = 0.0f) {
  const float ax = axis.x(), ay = axis.y(), az = axis.z(), a0 = axis.dot(origin);
  float lo = INFINITY, hi = -INFINITY;
  for (std::int32_t i : inliers) {
    if (distance_m != nullptr && !(distance_m[i] >= min_height_m)) continue;
    const CloudPoint& p = cloud.points[i];
    const float t = ax * p.x_m + ay * p.y_m + az * p.z_m - a0;
    lo = t < lo ? t : lo;
    hi = t > hi ? t : hi;
  }
  if (distance_m != nullptr && lo > hi) return;
  *t_min = lo;
  *t_max = hi;
}

// The gap pixels along [t_min, t_max] and within band_m across the line,
// into ws.band in the gap list's order. Four at a time: the points gathered
// by a transpose, both coordinates computed with the same operations in
// the same order as LinearForm's (so the same floats), the lanes in the
// band appended without a branch per pixel. This walk over the gap list
// runs for every line that reaches the centre line (more pixels than the
// cross test walks in a frame).
void collect_band(const OrganizedCloud& cloud, const LinearForm& along, const LinearForm& side,
                  float t_min, float t_max, float band_m, Workspace& ws) {
  using four_lanes::Floats4;
  using four_lanes::Ints4;
  const std::int32_t* gap = ws.gap.begin();
  const std::size_t n = ws.gap.size();
  const float* distance_m = ws.signed_distance_m.get();
  std::int32_t* band = ws.band.begin();
  std::size_t count = 0;
  std::size_t k = 0;
  // Each block writes four slots from `count`, at most k: within the list's
  // capacity, which is the gap list's (a slot per pixel).
  for (; k + 4 <= n; k += 4) {
    const CloudPoint* const p[4] = {cloud.points + gap[k], cloud.points + gap[k + 1],
                                    cloud.points + gap[k + 2], cloud.points + gap[k + 3]};
    Floats4 x, y, z, noise;
    four_lanes::load_four_points(p, &x, &y, &z, &noise);
    const Floats4 s = {distance_m[gap[k]], distance_m[gap[k + 1]], distance_m[gap[k + 2]],
                       distance_m[gap[k + 3]]};
    const Floats4 t = along.ex * x + along.ey * y + along.ez * z - s * along.en - along.e0;
    const Floats4 u = side.ex * x + side.ey * y + side.ez * z - s * side.en - side.e0;
    const Floats4 zero = {0.0f, 0.0f, 0.0f, 0.0f};
    const Floats4 u_abs = u < zero ? -u : u;
    const Ints4 in_band = (t >= t_min) & (t <= t_max) & (u_abs <= band_m);
    const std::uint32_t mask = four_lanes::lane_mask(in_band);
    for (int j = 0; j < 4; ++j) {
      band[count] = gap[k + j];
      count += (mask >> j) & 1u;
    }
  }
  for (; k < n; ++k) {
    const std::int32_t i = gap[k];
    const CloudPoint& p = cloud.points[i];
    const float s = distance_m[i];
    const float t = along(p, s);
    band[count] = i;
    count += t >= t_min && t <= t_max && std::fabs(side(p, s)) <= band_m;
  }
  ws.band.set_size(count);
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

namespace {

// Mode of the distances from the wall, 2 mm bins lightly smoothed, over the
// pixels in ws.band[0, n). NaN when there are none.
float front_face_height(const DetectorConfig& cfg, const Workspace& ws, std::size_t n) {
  constexpr int kBins = 64;
  constexpr float kBin_m = 0.002f;
  const float expected = cfg.handrail.bar_center_offset_m + 0.5f * cfg.handrail.bar_depth_m;
  const float base = expected - 0.5f * kBins * kBin_m;
  float hist[kBins] = {};
  for (std::size_t k = 0; k < n; ++k) {
    const int b = static_cast<int>((ws.signed_distance_m[ws.band[k]] - base) / kBin_m);
    if (b >= 0 && b < kBins) hist[b] += 1.0f;
  }
  float best = 0.0f;
  int peak = -1;
  for (int b = 2; b < kBins - 2; ++b) {
    const float v =
        hist[b - 2] + 2.0f * hist[b - 1] + 3.0f * hist[b] + 2.0f * hist[b + 1] + hist[b + 2];
    if (v > best) {
      best = v;
      peak = b;
    }
  }
  return peak < 0 ? NAN : base + (static_cast<float>(peak) + 0.5f) * kBin_m;
}

}  // namespace

bool estimate_center_line(const OrganizedCloud& cloud, const DetectorConfig& cfg, const Plane& wall,
                          const IndexList& inliers, Workspace& ws, CenterLine* line) {
  const std::size_t n = inliers.size();
  if (n < 3) return false;
  const Eigen::Vector3f& normal = wall.normal;

  const float nx = normal.x(), ny = normal.y(), nz = normal.z(), nd = wall.d;

  // Direction: principal axis of the inliers projected onto the wall.
  PointMoments on_wall;
  {
    const CloudPoint& p0 = cloud.points[inliers[0]];
    on_wall.set_reference(p0.x_m, p0.y_m, p0.z_m);
  }
  for (std::int32_t i : inliers) {
    const CloudPoint& p = cloud.points[i];
    const float s = nx * p.x_m + ny * p.y_m + nz * p.z_m + nd;
    on_wall.add(p.x_m - s * nx, p.y_m - s * ny, p.z_m - s * nz);
  }
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver;
  solver.computeDirect(on_wall.covariance());
  const Eigen::Vector3f direction = solver.eigenvectors().col(2).cast<float>();
  if (!direction.allFinite()) return false;
  Eigen::Matrix3f R = handrail_frame(normal, direction);
  Eigen::Vector3f axis = R.col(2);
  Eigen::Vector3f across = R.col(1);
  const Eigen::Vector3f origin = on_wall.mean().cast<float>();

  float t_min = 0.0f, t_max = 0.0f;
  inlier_extent(cloud, inliers, origin, axis, &t_min, &t_max);

  // Every raised pixel (the gap set) in a generous band around the line:
  // the cross test may have dropped a whole edge of the bar (a probe landing
  // on a cable), so its inliers alone could favour one face. A pixel's
  // coordinates along and across the line, after projection onto the wall,
  // are linear in the point and its wall distance s.
  const float band_m = 0.5f * cfg.handrail.bar_width_m + 0.02f;
  collect_band(cloud, LinearForm(axis, normal, origin), LinearForm(across, normal, origin), t_min,
               t_max, band_m, ws);
  const float front = front_face_height(cfg, ws, ws.band.size());
  if (!std::isfinite(front)) return false;

  // The pixels near the front face (the flat face of the ISS bar, the crown
  // of a round one) are the cleanest sample of the bar: they lie
  // symmetrically about its centre line from any viewing angle, and mixed
  // (flying) pixels at the bar's edges rarely reach that height. Refit the
  // direction to them, then take the middle of their spread across the bar
  // (2nd to 98th percentile).
  const float front_min_m = front - 0.3f * cfg.handrail.bar_depth_m;
  PointMoments front_face;
  front_face.set_reference(origin.x(), origin.y(), origin.z());
  for (std::int32_t i : ws.band) {
    const float s = ws.signed_distance_m[i];
    if (s < front_min_m) continue;
    const CloudPoint& p = cloud.points[i];
    front_face.add(p.x_m - s * nx, p.y_m - s * ny, p.z_m - s * nz);
  }
  if (front_face.n < 3.0) return false;
  solver.computeDirect(front_face.covariance());
  const Eigen::Vector3f band_direction = solver.eigenvectors().col(2).cast<float>();
  if (band_direction.allFinite()) {
    R = handrail_frame(normal, band_direction);
    axis = R.col(2);
    across = R.col(1);
  }
  std::size_t m = 0;
  {
    const LinearForm side(across, normal, origin);
    for (std::int32_t i : ws.band) {
      const float s = ws.signed_distance_m[i];
      if (s < front_min_m) continue;
      ws.values[m++] = side(cloud.points[i], s);
    }
  }
  float* v = ws.values.get();
  const std::size_t lo = m * 2 / 100, hi = m - 1 - m * 2 / 100;
  std::nth_element(v, v + lo, v + m);
  const float b_lo = v[lo];
  std::nth_element(v, v + hi, v + m);
  const float offset_across = 0.5f * (b_lo + v[hi]);
  // The inliers' extent along the refined axis; bar first, that of the
  // bar's own pixels (within its depth of the front).
  inlier_extent(cloud, inliers, origin, axis, &t_min, &t_max);
  if (cfg.bar_first) {
    inlier_extent(cloud, inliers, origin, axis, &t_min, &t_max, ws.signed_distance_m.get(),
                  front - cfg.handrail.bar_depth_m - cfg.gap_margin_m);
  }

  line->axis = axis;
  line->wall_normal = normal;
  line->point = origin + offset_across * across + cfg.handrail.bar_center_offset_m * normal;
  line->t_min_m = t_min;
  line->t_max_m = t_max;
  line->front_height_m = front;
  return true;
}

bool bar_front_height_test(const DetectorConfig& cfg, const CenterLine& line) {
  const float expected = cfg.handrail.bar_center_offset_m + 0.5f * cfg.handrail.bar_depth_m;
  return std::fabs(line.front_height_m - expected) < cfg.front_height_tolerance_m;
}

bool line_follows_front(const Eigen::Vector3f& candidate_direction, const CenterLine& line,
                        const DetectorConfig& cfg) {
  const float cos_turn = std::fabs(candidate_direction.dot(line.axis));
  return cos_turn >= std::cos(cfg.line_max_turn_deg * 3.14159265f / 180.0f);
}

bool touches_image_border(const OrganizedCloud& cloud, const IndexList& pixels, int margin_px) {
  const int w = static_cast<int>(cloud.width), h = static_cast<int>(cloud.height);
  for (std::int32_t i : pixels) {
    const int col = i % w, row = i / w;
    if (col < margin_px || row < margin_px || col >= w - margin_px || row >= h - margin_px) {
      return true;
    }
  }
  return false;
}

float allowed_end_drop_m(const DetectorConfig& cfg, const PixelScale& scale, float z_m) {
  const float pixel_m = scale.ok && scale.fx_px > 0.0f ? z_m / scale.fx_px : 0.0f;
  return cfg.end_drop_max_m + 2.0f * pixel_m;
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
