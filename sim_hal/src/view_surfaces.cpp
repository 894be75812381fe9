#include "sim_hal/view_surfaces.hpp"

#include <algorithm>
#include <cmath>

namespace sim_hal {
namespace {

constexpr float kParallelEps = 1e-9f;

// Each test takes the ray in the surface's local frame (o, d), narrows *t
// when it finds a nearer hit after t_min, and then sets *cos to
// |normal . d| (a rotation keeps dot products, so the local normal does).

bool hit_rect(const ViewSurface& s, const Eigen::Vector3f& o, const Eigen::Vector3f& d, float t_min,
              float* t, float* cos) {
  if (std::fabs(d.x()) < kParallelEps) return false;
  const float u = -o.x() / d.x();
  if (u <= t_min || u >= *t) return false;
  if (std::fabs(o.y() + u * d.y()) > s.half[1] || std::fabs(o.z() + u * d.z()) > s.half[2]) {
    return false;
  }
  *t = u;
  *cos = std::fabs(d.x());
  return true;
}

// A circle of radius r about (cx, cy) in the (x, y) plane of the ray's
// projection (px, py) = origin - centre, (dx, dy) = direction, a2 their
// squared length. The discriminant in its cross-product form, r^2 a2 -
// (p x d)^2, loses no precision for a ray passing far from the origin.
template <typename Accept>
void hit_circle(float px, float py, float dx, float dy, float a2, float r, float t_min, float* t,
                float* cos, bool* got, Accept accept) {
  const float cross = px * dy - py * dx;
  const float disc = r * r * a2 - cross * cross;
  if (disc < 0.0f) return;
  const float sq = std::sqrt(disc), b = px * dx + py * dy;
  for (float u : {(-b - sq) / a2, (-b + sq) / a2}) {
    if (u <= t_min || u >= *t || !accept(u)) continue;
    *t = u;
    *cos = std::fabs((px + u * dx) * dx + (py + u * dy) * dy) / r;
    *got = true;
  }
}

bool hit_cylinder(const ViewSurface& s, const Eigen::Vector3f& o, const Eigen::Vector3f& d,
                  float t_min, float* t, float* cos) {
  const float hl = s.half[0], r = s.radius;
  bool got = false;
  const float a2 = d.y() * d.y() + d.z() * d.z();
  if (a2 > kParallelEps) {
    // Most rays tested pass wide of a cable; the caps lie inside the
    // infinite cylinder, so such a ray misses them too.
    const float cross = o.y() * d.z() - o.z() * d.y();
    if (cross * cross > r * r * a2) return false;
    hit_circle(o.y(), o.z(), d.y(), d.z(), a2, r, t_min, t, cos, &got,
               [&](float u) { return std::fabs(o.x() + u * d.x()) <= hl; });
  }
  if (std::fabs(d.x()) > kParallelEps) {
    for (float side : {-hl, hl}) {
      const float u = (side - o.x()) / d.x();
      if (u <= t_min || u >= *t) continue;
      const float y = o.y() + u * d.y(), z = o.z() + u * d.z();
      if (y * y + z * z > r * r) continue;
      *t = u;
      *cos = std::fabs(d.x());
      got = true;
    }
  }
  return got;
}

bool hit_box(const ViewSurface& s, const Eigen::Vector3f& o, const Eigen::Vector3f& d, float t_min,
             float* t, float* cos) {
  float t0 = -INFINITY, t1 = INFINITY, entry_cos = 0.0f;
  for (int i = 0; i < 3; ++i) {
    if (std::fabs(d[i]) < kParallelEps) {
      if (std::fabs(o[i]) > s.half[i]) return false;
      continue;
    }
    const float a = (-s.half[i] - o[i]) / d[i], b = (s.half[i] - o[i]) / d[i];
    const float near_t = std::min(a, b), far_t = std::max(a, b);
    if (near_t > t0) {
      t0 = near_t;
      entry_cos = std::fabs(d[i]);
    }
    t1 = std::min(t1, far_t);
  }
  // Rays start outside boxes here, so the entry is the hit.
  if (t0 > t1 || t0 <= t_min || t0 >= *t) return false;
  *t = t0;
  *cos = entry_cos;
  return true;
}

bool inside_rounded_rect(float x, float y, float hx, float hy, float rc) {
  const float ax = std::fabs(x), ay = std::fabs(y);
  if (ax > hx || ay > hy) return false;
  if (ax <= hx - rc || ay <= hy - rc) return true;
  const float dx = ax - (hx - rc), dy = ay - (hy - rc);
  return dx * dx + dy * dy <= rc * rc;
}

bool hit_rounded_bar(const ViewSurface& s, const Eigen::Vector3f& o, const Eigen::Vector3f& d,
                     float t_min, float* t, float* cos) {
  const float hx = s.half[0], hy = s.half[1], hl = s.half[2], rc = s.radius;
  // A ray that misses the bar's box misses the bar.
  {
    float t_box = *t, cos_box = 0.0f;
    if (!hit_box(s, o, d, t_min, &t_box, &cos_box)) return false;
  }
  bool got = false;
  auto along_ok = [&](float u) { return std::fabs(o.z() + u * d.z()) <= hl; };
  // The four flat sides: x = +-hx between the corners in y, and y = +-hy.
  for (int axis = 0; axis < 2; ++axis) {
    const int other = 1 - axis;
    const float h = axis == 0 ? hx : hy, h_other = (axis == 0 ? hy : hx) - rc;
    if (std::fabs(d[axis]) <= kParallelEps) continue;
    for (float side : {-h, h}) {
      const float u = (side - o[axis]) / d[axis];
      if (u <= t_min || u >= *t) continue;
      if (std::fabs(o[other] + u * d[other]) > h_other || !along_ok(u)) continue;
      *t = u;
      *cos = std::fabs(d[axis]);
      got = true;
    }
  }
  // The rounded corners: quarter circles of the cross-section.
  const float a2 = d.x() * d.x() + d.y() * d.y();
  if (a2 > kParallelEps) {
    for (float cx : {-(hx - rc), hx - rc}) {
      for (float cy : {-(hy - rc), hy - rc}) {
        hit_circle(o.x() - cx, o.y() - cy, d.x(), d.y(), a2, rc, t_min, t, cos, &got, [&](float u) {
          const float x = o.x() + u * d.x(), y = o.y() + u * d.y();
          return (x - cx) * cx >= 0.0f && (y - cy) * cy >= 0.0f && along_ok(u);
        });
      }
    }
  }
  // The end caps.
  if (std::fabs(d.z()) > kParallelEps) {
    for (float side : {-hl, hl}) {
      const float u = (side - o.z()) / d.z();
      if (u <= t_min || u >= *t) continue;
      if (!inside_rounded_rect(o.x() + u * d.x(), o.y() + u * d.y(), hx, hy, rc)) continue;
      *t = u;
      *cos = std::fabs(d.z());
      got = true;
    }
  }
  return got;
}

// The local frame is the model's, moved to the centre of the model's box
// (half = the box's half sizes), so a float slab test rejects most rays
// before the walk down the mesh's hierarchy.
bool hit_mesh(const ViewSurface& s, const Eigen::Vector3f& o, const Eigen::Vector3f& d, float t_min,
              float* t, float* cos) {
  {
    float t_box = *t, cos_box = 0.0f;
    const bool starts_inside = std::fabs(o.x()) <= s.half[0] && std::fabs(o.y()) <= s.half[1] &&
                               std::fabs(o.z()) <= s.half[2];
    if (!starts_inside && !hit_box(s, o, d, t_min, &t_box, &cos_box)) return false;
  }
  Eigen::Vector3f normal;
  if (!s.mesh->intersect(o + s.mesh_box_center, d, t_min, *t, t, &normal)) return false;
  *cos = std::fabs(normal.dot(d));
  return true;
}

Eigen::Vector3d mesh_box_center(const Surface& s) {
  return 0.5 * (s.mesh.mesh->min_corner() + s.mesh.mesh->max_corner());
}

// Columns: the surface's local axes in the world frame; and its local
// origin in the world.
void local_frame(const Surface& s, Eigen::Matrix3d* axes_world, Eigen::Vector3d* center_world) {
  switch (s.kind) {
    case SurfaceKind::kRect:
      axes_world->col(0) = s.rect.normal;
      axes_world->col(1) = s.rect.u;
      axes_world->col(2) = s.rect.v;
      *center_world = s.rect.center;
      return;
    case SurfaceKind::kCylinder: {
      const Eigen::Vector3d e1 = s.cylinder.axis.unitOrthogonal();
      axes_world->col(0) = s.cylinder.axis;
      axes_world->col(1) = e1;
      axes_world->col(2) = s.cylinder.axis.cross(e1);
      *center_world = s.cylinder.center;
      return;
    }
    case SurfaceKind::kBox:
      *axes_world = s.box.R;
      *center_world = s.box.center;
      return;
    case SurfaceKind::kRoundedBar:
      axes_world->col(0) = s.bar.depth_dir;
      axes_world->col(1) = s.bar.axis.cross(s.bar.depth_dir);
      axes_world->col(2) = s.bar.axis;
      *center_world = s.bar.center;
      return;
    case SurfaceKind::kMesh:
      *axes_world = s.mesh.R;
      *center_world = s.mesh.R * mesh_box_center(s) + s.mesh.t;
      return;
  }
}

void set_sizes(const Surface& s, ViewSurface* v) {
  switch (s.kind) {
    case SurfaceKind::kRect:
      v->half[1] = static_cast<float>(s.rect.half_u);
      v->half[2] = static_cast<float>(s.rect.half_v);
      return;
    case SurfaceKind::kCylinder:
      v->half[0] = static_cast<float>(s.cylinder.half_length);
      v->radius = static_cast<float>(s.cylinder.radius);
      return;
    case SurfaceKind::kBox:
      for (int i = 0; i < 3; ++i) v->half[i] = static_cast<float>(s.box.half[i]);
      return;
    case SurfaceKind::kRoundedBar:
      v->half[0] = static_cast<float>(s.bar.half_depth);
      v->half[1] = static_cast<float>(s.bar.half_width);
      v->half[2] = static_cast<float>(s.bar.half_length);
      v->radius = static_cast<float>(s.bar.corner_radius);
      return;
    case SurfaceKind::kMesh: {
      v->mesh = s.mesh.mesh;
      v->mesh_box_center = mesh_box_center(s).cast<float>();
      const Eigen::Vector3d half = 0.5 * (s.mesh.mesh->max_corner() - s.mesh.mesh->min_corner());
      for (int i = 0; i < 3; ++i) v->half[i] = static_cast<float>(half[i]);
      return;
    }
  }
}

}  // namespace

void place_surfaces_in_view(const Scene& scene, const Eigen::Isometry3d& T_world_cam,
                            std::vector<ViewSurface>* out) {
  out->resize(scene.surfaces.size());
  const Eigen::Matrix3d R_world_cam = T_world_cam.rotation();
  const Eigen::Vector3d camera_world = T_world_cam.translation();
  const Eigen::Isometry3d T_cam_world = T_world_cam.inverse();
  for (std::size_t k = 0; k < scene.surfaces.size(); ++k) {
    const Surface& s = scene.surfaces[k];
    ViewSurface v;
    v.kind = s.kind;
    v.scene_index = static_cast<std::int32_t>(k);
    v.reflectivity = static_cast<float>(s.reflectivity);
    const Eigen::Vector3d bound_cam = T_cam_world * s.bound_center;
    v.bound_center = bound_cam.cast<float>();
    v.bound_radius = static_cast<float>(s.bound_radius);
    v.bound_center_sq_m2 =
        static_cast<float>(bound_cam.squaredNorm() - s.bound_radius * s.bound_radius);
    Eigen::Matrix3d axes_world = Eigen::Matrix3d::Identity();
    Eigen::Vector3d center_world = Eigen::Vector3d::Zero();
    local_frame(s, &axes_world, &center_world);
    v.R_local_cam = (axes_world.transpose() * R_world_cam).cast<float>();
    v.origin_local = (axes_world.transpose() * (camera_world - center_world)).cast<float>();
    set_sizes(s, &v);
    (*out)[k] = v;
  }
}

bool intersect_view(const ViewSurface* surfaces, const std::int32_t* ids, std::size_t count,
                    const Eigen::Vector3f& dir_cam, float t_min_m, float t_max_m, ViewHit* hit) {
  float t = t_max_m, cos = 0.0f;
  std::int32_t which = -1;
  for (std::size_t j = 0; j < count; ++j) {
    const ViewSurface& s = surfaces[ids[j]];
    // A wall's bounding sphere never rejects: its exact test is cheaper.
    if (s.kind != SurfaceKind::kRect) {
      const float along = s.bound_center.dot(dir_cam);
      if (along < -s.bound_radius || along - s.bound_radius > t) continue;
      if (s.bound_center_sq_m2 > along * along) continue;  // passes wide of the sphere
    }
    const Eigen::Vector3f d = s.R_local_cam * dir_cam;
    const Eigen::Vector3f& o = s.origin_local;
    // Branches on the kind rather than a switch's jump table: the lists are
    // grouped by kind, so each branch goes the same way as for the last
    // surface most of the time, which a jump table's target does not.
    bool got = false;
    if (s.kind == SurfaceKind::kCylinder) {
      got = hit_cylinder(s, o, d, t_min_m, &t, &cos);
    } else if (s.kind == SurfaceKind::kRect) {
      got = hit_rect(s, o, d, t_min_m, &t, &cos);
    } else if (s.kind == SurfaceKind::kBox) {
      got = hit_box(s, o, d, t_min_m, &t, &cos);
    } else if (s.kind == SurfaceKind::kRoundedBar) {
      got = hit_rounded_bar(s, o, d, t_min_m, &t, &cos);
    } else {
      got = hit_mesh(s, o, d, t_min_m, &t, &cos);
    }
    if (got) which = s.scene_index;
  }
  if (which < 0) return false;
  hit->t_m = t;
  hit->cos_incidence = cos;
  hit->surface = which;
  return true;
}

}  // namespace sim_hal
