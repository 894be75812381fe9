#include "estimator/handrail_pose.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

// The bar's ends (handrail_pose.hpp, detect_ends): the front's height
// along the bar, and the walk from each end of the inliers along the
// bar's image until it meets the wall, something in front, or the image's
// edge.
namespace estimator {
namespace {

Eigen::Vector3f point_of(const OrganizedCloud& cloud, std::int32_t i) {
  const CloudPoint& p = cloud.points[i];
  return {p.x_m, p.y_m, p.z_m};
}

}  // namespace

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

}  // namespace estimator
