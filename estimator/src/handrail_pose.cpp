#include "estimator/handrail_pose.hpp"

#include "estimator/moments.hpp"
#include "four_lanes.hpp"

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

namespace estimator {
namespace {

Eigen::Vector3f point_of(const OrganizedCloud& cloud, std::int32_t i) {
  const CloudPoint& p = cloud.points[i];
  return {p.x_m, p.y_m, p.z_m};
}

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
void inlier_extent(const OrganizedCloud& cloud, const IndexList& inliers,
                   const Eigen::Vector3f& origin, const Eigen::Vector3f& axis, float* t_min,
                   float* t_max) {
  const float ax = axis.x(), ay = axis.y(), az = axis.z(), a0 = axis.dot(origin);
  float lo = INFINITY, hi = -INFINITY;
  for (std::int32_t i : inliers) {
    const CloudPoint& p = cloud.points[i];
    const float t = ax * p.x_m + ay * p.y_m + az * p.z_m - a0;
    lo = t < lo ? t : lo;
    hi = t > hi ? t : hi;
  }
  *t_min = lo;
  *t_max = hi;
}

// The extent of the inliers that stand at the bar's own height (their
// distance to the surface at least min_height_m): an inlier lower than the
// bar's back is the surface beside or beyond it, which a line seen at a
// slant collects in its 2-D neighbourhood, and it says nothing about where
// the bar ends. Keeps t_min and t_max as they are when no inlier is that
// high.
void bar_pixel_extent(const OrganizedCloud& cloud, const IndexList& inliers,
                      const float* distance_m, float min_height_m, const Eigen::Vector3f& origin,
                      const Eigen::Vector3f& axis, float* t_min, float* t_max) {
  const float a0 = axis.dot(origin);
  float lo = INFINITY, hi = -INFINITY;
  for (std::int32_t i : inliers) {
    if (!(distance_m[i] >= min_height_m)) continue;
    const CloudPoint& p = cloud.points[i];
    const float t = axis.x() * p.x_m + axis.y() * p.y_m + axis.z() * p.z_m - a0;
    lo = t < lo ? t : lo;
    hi = t > hi ? t : hi;
  }
  if (lo > hi) return;
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
    bar_pixel_extent(cloud, inliers, ws.signed_distance_m.get(),
                     front - cfg.handrail.bar_depth_m - cfg.gap_margin_m, origin, axis, &t_min,
                     &t_max);
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

namespace {

// What the end walk sees across its path. Past the bar's own pixels (its
// inliers) the walk crosses gaps where something hid the bar, but it must
// not take raised ground for the bar: across the walk a bar's raised run
// is a bar's width wide, with a centimetre and a half to spare each side
// (and, seen obliquely, the leg at this end and the near side face reach
// aside of it in the image by the leg's projection); along a box's edge or
// over its top the run goes on.
class RaisedAcrossWalk {
 public:
  RaisedAcrossWalk(const OrganizedCloud& cloud, const DetectorConfig& cfg, const PixelScale& scale,
                   const Workspace& ws, const CenterLine& line, const Eigen::Vector3f& wall_normal,
                   float t_inner, float z_m, const Eigen::Vector2f& side, float outward_sign)
      : cloud_(cloud),
        ws_(ws),
        line_(line),
        side_(side),
        raised_min_m_(gap_min_m(cfg)),
        t_inner_(t_inner),
        outward_sign_(outward_sign) {
    const Eigen::Vector3f bar_end = line.point + t_inner * line.axis;
    const Eigen::Vector3f leg_foot = bar_end - cfg.handrail.bar_center_offset_m * wall_normal;
    float leg_aside_px = 0.0f;
    if (bar_end.z() > 0.0f && leg_foot.z() > 0.0f) {
      const Eigen::Vector2f leg_px(
          scale.fx_px * (leg_foot.x() / leg_foot.z() - bar_end.x() / bar_end.z()),
          scale.fy_px * (leg_foot.y() / leg_foot.z() - bar_end.y() / bar_end.z()));
      leg_aside_px = leg_px.dot(side);
    }
    const float bar_m = cfg.handrail.bar_width_m + 0.03f;
    run_max_px_ =
        std::fmax(scale.px_x(bar_m, z_m), scale.px_y(bar_m, z_m)) + std::fabs(leg_aside_px);
    run_limit_px_ = static_cast<int>(std::ceil(run_max_px_)) + 1;
  }

  // Whether the raised run across the walk through the band's pixel nearest
  // `at` (the walk's centre) is wider than a bar's. Each way it is followed
  // at most a bar's run: a step costs a few dozen lookups.
  bool wider_than_bar(const Eigen::Vector2f& at) const {
    for (const int j0 : {0, 1, -1, 2, -2}) {
      const Eigen::Vector2f from = at + side_ * static_cast<float>(j0);
      if (!raised(from)) continue;
      int run = 1;
      for (const float dir : {1.0f, -1.0f}) {
        for (int j = 1; j <= run_limit_px_ && raised(from + side_ * (dir * static_cast<float>(j)));
             ++j) {
          ++run;
        }
      }
      return static_cast<float>(run) > run_max_px_;
    }
    return false;
  }

  // Whether the pixel at `at` lies more than a centimetre past the last
  // inlier toward this end.
  bool past_inliers(const Eigen::Vector2f& at) const {
    const std::int32_t i = valid_pixel(at);
    if (i < 0) return false;
    const float t = (point_of(cloud_, i) - line_.point).dot(line_.axis);
    return outward_sign_ * (t - t_inner_) > 0.01f;
  }

 private:
  std::int32_t valid_pixel(const Eigen::Vector2f& px) const {
    const int col = static_cast<int>(std::lround(px.x()));
    const int row = static_cast<int>(std::lround(px.y()));
    if (col < 0 || row < 0 || col >= static_cast<int>(cloud_.width) ||
        row >= static_cast<int>(cloud_.height)) {
      return -1;
    }
    const std::int32_t i = row * static_cast<int>(cloud_.width) + col;
    return (ws_.flags[i] & kFlagValid) ? i : -1;
  }
  bool raised(const Eigen::Vector2f& px) const {
    const std::int32_t i = valid_pixel(px);
    return i >= 0 && ws_.signed_distance_m[i] >= raised_min_m_;
  }

  const OrganizedCloud& cloud_;
  const Workspace& ws_;
  const CenterLine& line_;
  Eigen::Vector2f side_;
  float raised_min_m_, t_inner_, outward_sign_;
  float run_max_px_ = 0.0f;
  int run_limit_px_ = 0;
};

}  // namespace

FrontAlongBar fit_front_along_bar(const OrganizedCloud& cloud, const DetectorConfig& cfg,
                                  const Workspace& ws, const IndexList& inliers,
                                  const CenterLine& line) {
  FrontAlongBar out;
  out.level_m = line.front_height_m;
  double st = 0, sh = 0, stt = 0, sth = 0, n = 0;
  for (std::int32_t i : inliers) {
    const float h = ws.signed_distance_m[i];
    if (!(h >= line.front_height_m - 0.5f * cfg.handrail.bar_depth_m)) continue;
    const double t = (point_of(cloud, i) - line.point).dot(line.axis);
    st += t;
    sh += h;
    stt += t * t;
    sth += t * h;
    n += 1.0;
  }
  // Ten pixels spread over a few centimetres at the least: else the level.
  const double det = n * stt - st * st;
  if (n < 10.0 || !(det > 1e-4 * n * n)) return out;
  out.slope = static_cast<float>((n * sth - st * sh) / det);
  out.level_m = static_cast<float>((sh - out.slope * st) / n);
  out.fitted = true;
  return out;
}

void detect_ends(const OrganizedCloud& cloud, const DetectorConfig& cfg, const PixelScale& scale,
                 const Workspace& ws, const IndexList& inliers, const CenterLine& line,
                 const Eigen::Vector3f& wall_normal, bool end_seen[2], float end_t_m[2],
                 float end_drop_m[2], float front_level_m, const FrontAlongBar* front) {
  end_seen[0] = end_seen[1] = false;
  end_t_m[0] = line.t_min_m;
  end_t_m[1] = line.t_max_m;
  if (end_drop_m != nullptr) end_drop_m[0] = end_drop_m[1] = 0.0f;
  // Where a pixel counts as at the front's height: within the front-height
  // test's tolerance and twice its noise (at most a centimetre more).
  auto front_tolerance = [&cfg](const CloudPoint& p) {
    const float noise = p.noise_m > 0.0f && p.noise_m < 0.05f ? p.noise_m : 0.0f;
    return cfg.front_height_tolerance_m + std::fmin(2.0f * noise, 0.01f);
  };
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

  const float front_a = front != nullptr ? front->level_m : front_level_m;
  const float front_b = front != nullptr ? front->slope : 0.0f;
  const auto front_at = [&](const CloudPoint& p) {
    return front_a + front_b * (Eigen::Vector3f(p.x_m, p.y_m, p.z_m) - line.point).dot(line.axis);
  };
  // The bar's own pixels: its depth below its front. Bar first, from the
  // front as measured (a handrail's front stands 7.3 to 12 cm over its
  // surface); otherwise the nominal handrail's window over the wall.
  const float depth_below_front = cfg.handrail.bar_depth_m + cfg.gap_margin_m;
  for (int end = 0; end < 2; ++end) {
    // Start at the mean pixel of the inliers within 2 cm of this end.
    const float t_end = end == 0 ? line.t_min_m : line.t_max_m;
    double ru = 0, rv = 0, rz = 0;
    int m = 0;
    float t_inner = t_end;
    for (std::int32_t i : inliers) {
      // Bar first, only the bar's own pixels (the surface beside a bar
      // seen at a slant is no place to start).
      if (front != nullptr &&
          !(ws.signed_distance_m[i] >= front_at(cloud.points[i]) - depth_below_front)) {
        continue;
      }
      const float t = (point_of(cloud, i) - line.point).dot(line.axis);
      if (std::fabs(t - t_end) < 0.02f) {
        ru += i % w;
        rv += i / w;
        rz += cloud.points[i].z_m;
        ++m;
        t_inner = end == 0 ? std::min(t_inner, t) : std::max(t_inner, t);
      }
    }
    if (m == 0) continue;
    // The last of the bar's own pixels at its front's height toward this
    // end (the inliers may run on down a ramp).
    float t_front = end == 0 ? INFINITY : -INFINITY;
    for (std::int32_t i : inliers) {
      if (ws.signed_distance_m[i] < front_at(cloud.points[i]) - front_tolerance(cloud.points[i])) {
        continue;
      }
      const float t = (point_of(cloud, i) - line.point).dot(line.axis);
      t_front = end == 0 ? std::min(t_front, t) : std::max(t_front, t);
    }
    if (!std::isfinite(t_front)) t_front = t_inner;
    Eigen::Vector2f start(static_cast<float>(ru / m), static_cast<float>(rv / m));
    // Point the image direction outward: toward this end along the bar.
    Eigen::Vector2f outward =
        start - Eigen::Vector2f(static_cast<float>(mu), static_cast<float>(mv));
    Eigen::Vector2f step = dir_px;
    if (outward.dot(step) < 0.0f) step = -step;
    const float z = static_cast<float>(rz / m);
    // The walk follows the bar as long as it stays on it (a gap in the
    // inliers, where a cable crossing behind the bar failed the cross test,
    // is no end), and looks at most end_search_m past its last bar pixel.
    // Bounded by the image's size.
    const int max_past_bar = static_cast<int>(
        std::ceil(std::fmax(scale.px_x(cfg.end_search_m, z), scale.px_y(cfg.end_search_m, z))));
    const int max_steps = static_cast<int>(cloud.width + cloud.height);
    // Each step looks at a short band across the walk (+-2 px), and while
    // on the bar recentres the walk on the bar's pixels in that band: the
    // direction from fragmentary inliers may be a few degrees off, and lens
    // distortion bends the bar's image, so a straight walk would slide off
    // its side and mistake the wall beside it for the wall past its end.
    const Eigen::Vector2f side(-step.y(), step.x());
    const RaisedAcrossWalk across_walk(cloud, cfg, scale, ws, line, wall_normal, t_inner, z, side,
                                       end == 0 ? -1.0f : 1.0f);
    int invalid_run = 0, past_bar = 0;
    float t_bar = t_inner;
    // The farthest raised pixel (above the wall's tolerance, below what
    // would hide the end) before the walk meets the wall. The low half of
    // a cable's ramp lies under the gap window's floor, where t_bar does
    // not see it; a handrail's leg stands flush with the bar's end, so its
    // raised structure ends with the bar. Raised counts from the surface
    // the bar was seated on: a seat track runs on past a handrail's end at
    // that surface's level.
    float t_raised = t_inner;
    bool raised_runs_on = true;
    // Bar first, raised is what stands at the bar's own height, down to a
    // centimetre under its back face: the surface its legs stand on, and a
    // track or strip a few centimetres proud of it that runs on past the
    // leg, are not, whatever level the surface fitted around the bar has.
    const float raised_min_m =
        front != nullptr
            ? std::fmax(cfg.wall_tolerance_m, front_a - cfg.handrail.bar_depth_m - 0.01f)
            : std::fmax(cfg.wall_tolerance_m,
                        front_level_m - line.front_height_m + cfg.wall_tolerance_m);
    Eigen::Vector2f centre = start;
    for (int k = 1; k <= max_steps && past_bar <= max_past_bar; ++k) {
      centre += step;
      bool any_valid = false, on_bar = false, in_front = false, all_wall = true,
           raised_here = false;
      // Raised ground wider than a bar is neither the bar nor its end.
      const bool plateau = across_walk.past_inliers(centre) && across_walk.wider_than_bar(centre);
      float across_sum = 0.0f;
      int across_n = 0, in_image = 0;
      for (int j = -2; j <= 2; ++j) {
        const Eigen::Vector2f px = centre + side * static_cast<float>(j);
        const int col = static_cast<int>(std::lround(px.x()));
        const int row = static_cast<int>(std::lround(px.y()));
        if (col < 0 || row < 0 || col >= w || row >= static_cast<int>(cloud.height)) {
          // The walk itself off the image: the end is not in view. A band
          // pixel off it beside an end a pixel or two inside the border
          // says nothing either way.
          if (j == 0) in_front = true;
          continue;
        }
        ++in_image;
        const std::int32_t i = row * w + col;
        if (!(ws.flags[i] & kFlagValid)) {
          all_wall = false;
          continue;
        }
        any_valid = true;
        const float s = ws.signed_distance_m[i];
        const float front_here = front_at(cloud.points[i]);
        const float lo = front != nullptr ? front_here - depth_below_front : gap_min_m(cfg);
        const float hi = front != nullptr ? front_here + cfg.gap_margin_m : gap_max_m(cfg);
        if (s >= cfg.wall_tolerance_m) all_wall = false;
        if (s >= raised_min_m && s <= hi + 0.02f && raised_runs_on) {
          raised_here = true;
          const float t = (point_of(cloud, i) - line.point).dot(line.axis);
          t_raised = end == 0 ? std::min(t_raised, t) : std::max(t_raised, t);
        }
        if (s > hi + 0.02f) in_front = true;
        if (s >= lo && s <= hi + 0.02f && !plateau) {
          on_bar = true;
          across_sum += static_cast<float>(j);
          ++across_n;
          const float t = (point_of(cloud, i) - line.point).dot(line.axis);
          t_bar = end == 0 ? std::min(t_bar, t) : std::max(t_bar, t);
          if (s >= front_here - front_tolerance(cloud.points[i])) {
            t_front = end == 0 ? std::min(t_front, t) : std::max(t_front, t);
          }
        }
      }
      if (in_front) break;  // something hides the end, or the image ends
      if (!any_valid) {
        if (++invalid_run > 3) break;
        continue;
      }
      invalid_run = 0;
      // Only raised structure that runs on step by step from the bar
      // counts: a step whose valid pixels all lie low ends it, so dropouts
      // and noise farther on along a seat track do not.
      raised_runs_on = raised_runs_on && raised_here;
      if (all_wall && !on_bar && in_image >= 3) {
        end_seen[end] = true;
        break;
      }
      // At most a quarter pixel per step: enough to hold a straight bar whose
      // direction is off by up to ~14 deg, too little to follow a cable
      // that bends away from it.
      if (across_n > 0) {
        const float shift = across_sum / static_cast<float>(across_n);
        centre += side * std::fmax(-0.25f, std::fmin(0.25f, shift));
      }
      past_bar = on_bar ? 0 : past_bar + 1;
    }
    end_t_m[end] = t_bar;
    if (end_drop_m != nullptr) end_drop_m[end] = std::fabs(t_raised - t_front);
  }
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
