#include "sim_hal/scene.hpp"

#include "scene_hull.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

namespace sim_hal {
namespace {

using detail::set_box_hull;

constexpr double kParallelEps = 1e-12;

// The paper's model: legs 6.5 cm high under the ends of a 3.5 cm round bar.
constexpr double kRoundRadius = 0.0175, kRoundLegHeight = 0.065;
// The ISS bar (from the meshes in shared/assets/handrails).
constexpr double kIssDepth = 0.035, kIssWidth = 0.019, kIssCorner = 0.008, kIssOffset = 0.061;
constexpr double kIssLegAlong = 0.045, kIssLegAcross = 0.025;
// The module rail: a plain box bar, 3.4 cm deep by 1.9 cm across, centre
// line 6.1 cm off the surface (the station's 6.1 to 6.3 cm), on box legs.
constexpr double kModuleDepth = 0.034, kModuleWidth = 0.019, kModuleOffset = 0.061;
constexpr double kModuleLegAlong = 0.040, kModuleLegAcross = 0.025;
// Tracks and strips reach this far into the face under them, so that no
// ray slips through a crack between two boxes that only touch.
constexpr double kEmbedM = 0.002;

void keep_nearest(double t, const Eigen::Vector3d& n, double t_min, double* best_t,
                  Eigen::Vector3d* best_n) {
  if (t > t_min && t < *best_t) {
    *best_t = t;
    *best_n = n;
  }
}

bool hit_rect(const RectSurface& r, const Eigen::Vector3d& o, const Eigen::Vector3d& d,
              double t_min, double* t, Eigen::Vector3d* n) {
  const double denom = d.dot(r.normal);
  if (std::fabs(denom) < kParallelEps) return false;
  const double s = (r.center - o).dot(r.normal) / denom;
  if (s <= t_min || s >= *t) return false;
  const Eigen::Vector3d q = o + s * d - r.center;
  if (std::fabs(q.dot(r.u)) > r.half_u || std::fabs(q.dot(r.v)) > r.half_v) return false;
  *t = s;
  *n = r.normal;
  return true;
}

bool hit_cylinder(const CylinderSurface& c, const Eigen::Vector3d& o, const Eigen::Vector3d& d,
                  double t_min, double* t, Eigen::Vector3d* n) {
  const Eigen::Vector3d oc = o - c.center;
  const double oa = oc.dot(c.axis), da = d.dot(c.axis);
  const Eigen::Vector3d op = oc - oa * c.axis, dp = d - da * c.axis;
  const double a = dp.squaredNorm(), b = 2.0 * op.dot(dp),
               k = op.squaredNorm() - c.radius * c.radius;
  const double before = *t;
  if (a > kParallelEps) {
    const double disc = b * b - 4.0 * a * k;
    if (disc >= 0.0) {
      const double sq = std::sqrt(disc);
      for (double s : {(-b - sq) / (2.0 * a), (-b + sq) / (2.0 * a)}) {
        // The normal is worked out only for a hit that wins.
        if (s > t_min && s < *t && std::fabs(oa + s * da) <= c.half_length) {
          *t = s;
          *n = (op + s * dp) / c.radius;
        }
      }
    }
  }
  if (std::fabs(da) > kParallelEps) {
    for (double sign : {-1.0, 1.0}) {
      const double s = (sign * c.half_length - oa) / da;
      if ((op + s * dp).squaredNorm() <= c.radius * c.radius) {
        keep_nearest(s, sign * c.axis, t_min, t, n);
      }
    }
  }
  return *t < before;
}

bool hit_box(const BoxSurface& b, const Eigen::Vector3d& o, const Eigen::Vector3d& d, double t_min,
             double* t, Eigen::Vector3d* n) {
  const Eigen::Vector3d ol = b.R.transpose() * (o - b.center), dl = b.R.transpose() * d;
  double t0 = -1e300, t1 = 1e300;
  int axis0 = -1;
  double sign0 = 0.0;
  for (int i = 0; i < 3; ++i) {
    if (std::fabs(dl[i]) < kParallelEps) {
      if (std::fabs(ol[i]) > b.half[i]) return false;
      continue;
    }
    double a = (-b.half[i] - ol[i]) / dl[i], c = (b.half[i] - ol[i]) / dl[i];
    double sign = -1.0;
    if (a > c) {
      std::swap(a, c);
      sign = 1.0;
    }
    if (a > t0) {
      t0 = a;
      axis0 = i;
      sign0 = sign;
    }
    t1 = std::fmin(t1, c);
  }
  if (t0 > t1 || axis0 < 0) return false;
  if (t0 <= t_min || t0 >= *t) return false;  // rays start outside boxes here
  *t = t0;
  *n = sign0 * b.R.col(axis0);
  return true;
}

bool inside_rounded_rect(double x, double y, double hx, double hy, double rc) {
  const double ax = std::fabs(x), ay = std::fabs(y);
  if (ax > hx || ay > hy) return false;
  if (ax <= hx - rc || ay <= hy - rc) return true;
  const double dx = ax - (hx - rc), dy = ay - (hy - rc);
  return dx * dx + dy * dy <= rc * rc;
}

bool hit_rounded_bar(const RoundedBarSurface& b, const Eigen::Vector3d& o, const Eigen::Vector3d& d,
                     double t_min, double* t, Eigen::Vector3d* n) {
  const Eigen::Vector3d e_w = b.axis.cross(b.depth_dir);
  const Eigen::Vector3d oc = o - b.center;
  const double ox = oc.dot(b.depth_dir), oy = oc.dot(e_w), oa = oc.dot(b.axis);
  const double dx = d.dot(b.depth_dir), dy = d.dot(e_w), da = d.dot(b.axis);
  const double hx = b.half_depth, hy = b.half_width, rc = b.corner_radius, hl = b.half_length;
  const double before = *t;
  auto axial_ok = [&](double s) { return std::fabs(oa + s * da) <= hl; };
  // Flat sides.
  for (double sx : {-1.0, 1.0}) {
    if (std::fabs(dx) > kParallelEps) {
      const double s = (sx * hx - ox) / dx;
      if (std::fabs(oy + s * dy) <= hy - rc && axial_ok(s))
        keep_nearest(s, sx * b.depth_dir, t_min, t, n);
    }
    if (std::fabs(dy) > kParallelEps) {
      const double s = (sx * hy - oy) / dy;
      if (std::fabs(ox + s * dx) <= hx - rc && axial_ok(s)) keep_nearest(s, sx * e_w, t_min, t, n);
    }
  }
  // Rounded corners: circles in the cross-section.
  const double a2 = dx * dx + dy * dy;
  if (a2 > kParallelEps) {
    for (double cx : {-(hx - rc), hx - rc}) {
      for (double cy : {-(hy - rc), hy - rc}) {
        const double px = ox - cx, py = oy - cy;
        const double bq = 2.0 * (px * dx + py * dy), cq = px * px + py * py - rc * rc;
        const double disc = bq * bq - 4.0 * a2 * cq;
        if (disc < 0.0) continue;
        const double sq = std::sqrt(disc);
        for (double s : {(-bq - sq) / (2.0 * a2), (-bq + sq) / (2.0 * a2)}) {
          const double x = ox + s * dx, y = oy + s * dy;
          if ((x - cx) * cx < 0.0 || (y - cy) * cy < 0.0 || !axial_ok(s)) continue;
          const Eigen::Vector3d nn = ((x - cx) * b.depth_dir + (y - cy) * e_w) / rc;
          keep_nearest(s, nn, t_min, t, n);
        }
      }
    }
  }
  // End caps.
  if (std::fabs(da) > kParallelEps) {
    for (double sa : {-1.0, 1.0}) {
      const double s = (sa * hl - oa) / da;
      if (inside_rounded_rect(ox + s * dx, oy + s * dy, hx, hy, rc))
        keep_nearest(s, sa * b.axis, t_min, t, n);
    }
  }
  return *t < before;
}

bool misses_bound(const Surface& s, const Eigen::Vector3d& o, const Eigen::Vector3d& d,
                  double t_max) {
  const Eigen::Vector3d oc = s.bound_center - o;
  const double along = oc.dot(d);
  if (along < -s.bound_radius || along - s.bound_radius > t_max) return true;
  return (oc - along * d).squaredNorm() > s.bound_radius * s.bound_radius;
}

Surface make_cylinder(const Eigen::Vector3d& center, const Eigen::Vector3d& axis, double radius,
                      double half_length, std::int32_t id, double reflectivity) {
  Surface s{};
  s.kind = SurfaceKind::kCylinder;
  s.object_id = id;
  s.reflectivity = reflectivity;
  s.cylinder = {center, axis.normalized(), radius, half_length};
  s.bound_center = center;
  s.bound_radius = std::hypot(radius, half_length);
  s.hull[0] = center - half_length * s.cylinder.axis;
  s.hull[1] = center + half_length * s.cylinder.axis;
  s.hull_points = 2;
  s.hull_radius = radius;
  return s;
}

Surface make_box(const Eigen::Vector3d& center, const Eigen::Matrix3d& R,
                 const Eigen::Vector3d& half, std::int32_t id, double reflectivity) {
  Surface s{};
  s.kind = SurfaceKind::kBox;
  s.object_id = id;
  s.reflectivity = reflectivity;
  s.box = {center, R, half};
  s.bound_center = center;
  s.bound_radius = half.norm();
  set_box_hull(center, R, half, &s);
  return s;
}

}  // namespace

// The 8 corners of an oriented box as a surface's hull.
void detail::set_box_hull(const Eigen::Vector3d& center, const Eigen::Matrix3d& R,
                          const Eigen::Vector3d& half, Surface* s) {
  for (int k = 0; k < 8; ++k) {
    const Eigen::Vector3d corner((k & 1) ? half.x() : -half.x(), (k & 2) ? half.y() : -half.y(),
                                 (k & 4) ? half.z() : -half.z());
    s->hull[k] = center + R * corner;
  }
  s->hull_points = 8;
  s->hull_radius = 0.0;
}

const char* to_string(HandrailKind kind) {
  switch (kind) {
    case HandrailKind::kPaperRound:
      return "round";
    case HandrailKind::kIss:
      return "iss";
    case HandrailKind::kIssMesh:
      return "iss_mesh";
    case HandrailKind::kModuleRail:
      return "module_rail";
    case HandrailKind::kInModuleMesh:
      return "in_module_mesh";
  }
  return "unknown";
}

double Handrail::center_offset_m() const {
  switch (kind) {
    case HandrailKind::kPaperRound:
      return kRoundLegHeight + kRoundRadius;
    case HandrailKind::kIss:
      return kIssOffset;
    case HandrailKind::kIssMesh:
      return mesh_bar.center_offset_m();
    case HandrailKind::kModuleRail:
      return kModuleOffset;
    case HandrailKind::kInModuleMesh:
      return (given_ends[0] - foot_center).dot(normal.normalized());
  }
  return 0.0;
}

Eigen::Vector3d Handrail::end_point(int end) const {
  if (kind == HandrailKind::kInModuleMesh) return given_ends[end == 0 ? 0 : 1];
  if (kind == HandrailKind::kIssMesh) {
    const Eigen::Vector3d n = normal.normalized(), a = axis.normalized();
    const double across = 0.5 * (mesh_bar.y_min + mesh_bar.y_max);
    return foot_center + center_offset_m() * n + across * a.cross(n) +
           (end == 0 ? mesh_bar.z_min : mesh_bar.z_max) * a;
  }
  const double sign = end == 0 ? -1.0 : 1.0;
  return foot_center + center_offset_m() * normal + sign * 0.5 * bar_length_m * axis;
}

void Scene::add_wall(const Eigen::Vector3d& center, const Eigen::Vector3d& normal,
                     const Eigen::Vector3d& up, double width_m, double height_m,
                     double reflectivity) {
  Surface s{};
  s.kind = SurfaceKind::kRect;
  s.object_id = -1;
  s.reflectivity = reflectivity;
  const Eigen::Vector3d n = normal.normalized();
  const Eigen::Vector3d v = (up - up.dot(n) * n).normalized();
  s.rect = {center, n, v.cross(n), v, 0.5 * width_m, 0.5 * height_m};
  s.bound_center = center;
  s.bound_radius = 0.5 * std::hypot(width_m, height_m);
  for (int k = 0; k < 4; ++k) {
    s.hull[k] = center + ((k & 1) ? 0.5 : -0.5) * width_m * s.rect.u +
                ((k & 2) ? 0.5 : -0.5) * height_m * s.rect.v;
  }
  s.hull_points = 4;
  surfaces.push_back(s);
}

void Scene::add_handrail(const Handrail& h) {
  const std::int32_t id = static_cast<std::int32_t>(handrails.size());
  handrails.push_back(h);
  const Eigen::Vector3d n = h.normal.normalized(), a = h.axis.normalized();
  const double half = 0.5 * h.bar_length_m;
  const Eigen::Vector3d bar_center = h.foot_center + h.center_offset_m() * n;
  if (h.kind == HandrailKind::kIssMesh) {
    Surface s{};
    s.kind = SurfaceKind::kMesh;
    s.object_id = id;
    s.reflectivity = h.reflectivity;
    s.mesh.mesh = h.mesh.get();
    s.mesh.R.col(0) = n;
    s.mesh.R.col(1) = a.cross(n);
    s.mesh.R.col(2) = a;
    s.mesh.t = h.foot_center;
    const Eigen::Vector3d lo = h.mesh->min_corner(), hi = h.mesh->max_corner();
    const Eigen::Vector3d center = s.mesh.R * (0.5 * (lo + hi)) + s.mesh.t;
    // The hull: a capsule along the rail around the model's box (a long,
    // thin box's eight corners would cull far less once the camera rolls).
    const double half_along = 0.5 * (hi.z() - lo.z());
    s.hull[0] = center - half_along * a;
    s.hull[1] = center + half_along * a;
    s.hull_points = 2;
    s.hull_radius = 0.5 * std::hypot(hi.x() - lo.x(), hi.y() - lo.y());
    s.bound_center = center;
    s.bound_radius = 0.5 * (hi - lo).norm();
    surfaces.push_back(s);
    return;
  }
  if (h.kind == HandrailKind::kPaperRound) {
    surfaces.push_back(make_cylinder(bar_center, a, kRoundRadius, half, id, h.reflectivity));
    for (double sign : {-1.0, 1.0}) {
      const Eigen::Vector3d leg =
          h.foot_center + sign * (half - kRoundRadius) * a + 0.5 * kRoundLegHeight * n;
      surfaces.push_back(
          make_cylinder(leg, n, kRoundRadius, 0.5 * kRoundLegHeight, id, h.reflectivity));
    }
    return;
  }
  Eigen::Matrix3d R;
  R.col(0) = n;
  R.col(1) = a.cross(n);
  R.col(2) = a;
  if (h.kind == HandrailKind::kModuleRail) {
    Surface bar =
        make_box(bar_center, R, Eigen::Vector3d(0.5 * kModuleDepth, 0.5 * kModuleWidth, half), id,
                 h.reflectivity);
    // A capsule along the bar, as for the rounded bar: a long box's eight
    // corners cull far less once the camera rolls.
    bar.hull[0] = bar_center - half * a;
    bar.hull[1] = bar_center + half * a;
    bar.hull_points = 2;
    bar.hull_radius = 0.5 * std::hypot(kModuleDepth, kModuleWidth);
    surfaces.push_back(bar);
    for (double sign : {-1.0, 1.0}) {
      const Eigen::Vector3d leg =
          h.foot_center + sign * (half - 0.5 * kModuleLegAlong) * a + 0.5 * kModuleOffset * n;
      surfaces.push_back(make_box(
          leg, R,
          Eigen::Vector3d(0.5 * kModuleOffset, 0.5 * kModuleLegAcross, 0.5 * kModuleLegAlong), id,
          h.reflectivity));
    }
    return;
  }
  Surface bar{};
  bar.kind = SurfaceKind::kRoundedBar;
  bar.object_id = id;
  bar.reflectivity = h.reflectivity;
  bar.bar = {bar_center, a, n, 0.5 * kIssDepth, 0.5 * kIssWidth, kIssCorner, half};
  bar.bound_center = bar_center;
  bar.bound_radius =
      std::sqrt(half * half + 0.25 * (kIssDepth * kIssDepth + kIssWidth * kIssWidth));
  bar.hull[0] = bar_center - half * a;
  bar.hull[1] = bar_center + half * a;
  bar.hull_points = 2;
  bar.hull_radius = 0.5 * std::hypot(kIssDepth, kIssWidth);
  surfaces.push_back(bar);
  for (double sign : {-1.0, 1.0}) {
    const Eigen::Vector3d leg =
        h.foot_center + sign * (half - 0.5 * kIssLegAlong) * a + 0.5 * kIssOffset * n;
    surfaces.push_back(
        make_box(leg, R, Eigen::Vector3d(0.5 * kIssOffset, 0.5 * kIssLegAcross, 0.5 * kIssLegAlong),
                 id, h.reflectivity));
  }
}

void Scene::add_cable(const std::vector<Eigen::Vector3d>& points, double diameter_m,
                      double reflectivity) {
  for (std::size_t k = 1; k < points.size(); ++k) {
    const Eigen::Vector3d seg = points[k] - points[k - 1];
    const double len = seg.norm();
    if (len < 1e-6) continue;
    surfaces.push_back(make_cylinder(0.5 * (points[k] + points[k - 1]), seg / len, 0.5 * diameter_m,
                                     0.5 * len + 0.25 * diameter_m, -1, reflectivity));
  }
}

void Scene::add_box(const Eigen::Vector3d& center, const Eigen::Matrix3d& R,
                    const Eigen::Vector3d& size_m, double reflectivity) {
  surfaces.push_back(make_box(center, R, 0.5 * size_m, -1, reflectivity));
}

void Scene::add_rect(const Eigen::Vector3d& center, const Eigen::Vector3d& normal,
                     const Eigen::Vector3d& u, const Eigen::Vector3d& v, double half_u_m,
                     double half_v_m, double reflectivity) {
  Surface s{};
  s.kind = SurfaceKind::kRect;
  s.object_id = -1;
  s.reflectivity = reflectivity;
  s.rect = {center, normal, u, v, half_u_m, half_v_m};
  s.bound_center = center;
  s.bound_radius = std::hypot(half_u_m, half_v_m);
  for (int k = 0; k < 4; ++k) {
    s.hull[k] =
        center + ((k & 1) ? half_u_m : -half_u_m) * u + ((k & 2) ? half_v_m : -half_v_m) * v;
  }
  s.hull_points = 4;
  surfaces.push_back(s);
}

Eigen::Vector3d RackWall::unit_normal() const {
  return normal.normalized();
}

Eigen::Vector3d RackWall::unit_v() const {
  const Eigen::Vector3d n = unit_normal();
  return (up - up.dot(n) * n).normalized();
}

Eigen::Vector3d RackWall::unit_u() const {
  return unit_v().cross(unit_normal());
}

Eigen::Vector3d RackWall::point(double u_m, double v_m, double depth_m) const {
  return center + u_m * unit_u() + v_m * unit_v() + depth_m * unit_normal();
}

void Scene::add_rack_wall(const RackWall& w) {
  rack_walls.push_back(w);
  const Eigen::Vector3d n = w.unit_normal(), u = w.unit_u(), v = w.unit_v();
  Eigen::Matrix3d R_wall;  // box axes: normal, u, v
  R_wall.col(0) = n;
  R_wall.col(1) = u;
  R_wall.col(2) = v;
  // A box over a wall rectangle between two depths.
  auto slab = [&](const WallRect& r, double back_m, double front_m, double reflectivity) {
    const Eigen::Vector3d c =
        w.point(0.5 * (r.u0 + r.u1), 0.5 * (r.v0 + r.v1), 0.5 * (back_m + front_m));
    surfaces.push_back(make_box(
        c, R_wall, Eigen::Vector3d(0.5 * (front_m - back_m), 0.5 * r.width_m(), 0.5 * r.height_m()),
        -1, reflectivity));
  };
  for (const RackWall::Face& f : w.faces) slab(f.rect, w.back_depth_m, f.depth_m, f.reflectivity);
  for (const RackWall::SeatTrack& t : w.seat_tracks) {
    const Eigen::Vector2d d = t.to - t.from;
    const double len = d.norm();
    if (len < 1e-6) continue;
    const Eigen::Vector3d along = (d.x() * u + d.y() * v) / len;
    Eigen::Matrix3d R;
    R.col(0) = n;
    R.col(1) = along.cross(n);
    R.col(2) = along;
    const Eigen::Vector2d mid = 0.5 * (t.from + t.to);
    const double back = t.base_depth_m - kEmbedM, front = t.top_depth_m();
    surfaces.push_back(make_box(w.point(mid.x(), mid.y(), 0.5 * (back + front)), R,
                                Eigen::Vector3d(0.5 * (front - back), 0.5 * t.width_m, 0.5 * len),
                                -1, t.reflectivity));
  }
  for (const RackWall::Recess& r : w.recesses) {
    const double cu = 0.5 * (r.rect.u0 + r.rect.u1), cv = 0.5 * (r.rect.v0 + r.rect.v1);
    const double hu = 0.5 * r.rect.width_m(), hv = 0.5 * r.rect.height_m();
    if (r.has_back) add_rect(w.point(cu, cv, r.depth_m), n, u, v, hu, hv, r.reflectivity);
    if (!r.side_walls) continue;
    const double depth_mid = 0.5 * (r.depth_m + r.rim_depth_m);
    const double half_depth = 0.5 * (r.rim_depth_m - r.depth_m);
    for (double sign : {-1.0, 1.0}) {
      // The walls at u0 and u1 (normal along u), then at v0 and v1.
      add_rect(w.point(cu + sign * hu, cv, depth_mid), u, n, v, half_depth, hv, r.reflectivity);
      add_rect(w.point(cu, cv + sign * hv, depth_mid), v, n, u, half_depth, hu, r.reflectivity);
    }
  }
  for (const RackWall::Strip& s : w.strips) {
    slab(s.rect, s.base_depth_m - kEmbedM, s.base_depth_m + s.height_m, s.reflectivity);
  }
}

void detail::set_mesh_surface(const std::shared_ptr<const TriangleMesh>& mesh,
                              const Eigen::Matrix3d& R, const Eigen::Vector3d& t, Surface* s) {
  s->mesh.mesh = mesh.get();
  s->mesh.R = R;
  s->mesh.t = t;
  const Eigen::Vector3d lo = mesh->min_corner(), hi = mesh->max_corner();
  s->bound_center = R * (0.5 * (lo + hi)) + t;
  s->bound_radius = 0.5 * (hi - lo).norm();
  // The model's box as the hull: a camera inside a module sees it behind
  // the image plane, and every tile keeps it.
  set_box_hull(s->bound_center, R, 0.5 * (hi - lo), s);
}

void Scene::add_mesh(const SceneMesh& m, double reflectivity) {
  meshes.push_back(m);
  Surface s{};
  s.kind = SurfaceKind::kMesh;
  s.object_id = -1;
  s.reflectivity = reflectivity;
  detail::set_mesh_surface(meshes.back().mesh, m.R, m.t, &s);
  meshes.back().surface = static_cast<std::int32_t>(surfaces.size());
  surfaces.push_back(s);
}

bool intersect_scene(const Scene& scene, const Eigen::Vector3d& o, const Eigen::Vector3d& d,
                     double t_min, double t_max, Hit* hit) {
  double t = t_max;
  Eigen::Vector3d n = Eigen::Vector3d::Zero();
  std::int32_t which = -1;
  for (std::size_t j = 0; j < scene.surfaces.size(); ++j) {
    const std::int32_t k = static_cast<std::int32_t>(j);
    const Surface& s = scene.surfaces[j];
    // A wall's bounding sphere never rejects: its exact test is cheaper.
    if (s.kind != SurfaceKind::kRect && misses_bound(s, o, d, t)) continue;
    bool got = false;
    switch (s.kind) {
      case SurfaceKind::kRect:
        got = hit_rect(s.rect, o, d, t_min, &t, &n);
        break;
      case SurfaceKind::kCylinder:
        got = hit_cylinder(s.cylinder, o, d, t_min, &t, &n);
        break;
      case SurfaceKind::kBox:
        got = hit_box(s.box, o, d, t_min, &t, &n);
        break;
      case SurfaceKind::kRoundedBar:
        got = hit_rounded_bar(s.bar, o, d, t_min, &t, &n);
        break;
      case SurfaceKind::kMesh: {
        // Into the model frame (a rotation keeps t), and the normal back.
        const Eigen::Vector3d ol = s.mesh.R.transpose() * (o - s.mesh.t);
        const Eigen::Vector3d dl = s.mesh.R.transpose() * d;
        MeshHit mh;
        got = s.mesh.mesh->intersect(ol, dl, t_min, t, &mh);
        if (got) {
          t = mh.t;
          n = s.mesh.R * mh.normal;
        }
        break;
      }
    }
    if (got) which = k;
  }
  if (which < 0) return false;
  hit->t = t;
  hit->normal = n.dot(d) > 0.0 ? Eigen::Vector3d(-n) : n;
  hit->surface = which;
  return true;
}

}  // namespace sim_hal
