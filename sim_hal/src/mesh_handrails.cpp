// The handrails a module mesh models itself (Scene::add_mesh_handrails):
// their triangles split off the module into surfaces of their own.
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <memory>
#include <vector>

#include "scene_hull.hpp"
#include "sim_hal/scene.hpp"

namespace sim_hal {

namespace {

// Whether a model-frame point lies in a modelled handrail's box (the
// centre line from e0 along a, n toward the room, w across).
bool in_handrail_box(const MeshHandrail& h, const Eigen::Vector3d& p) {
  const Eigen::Vector3d a = (h.ends[1] - h.ends[0]).normalized();
  const Eigen::Vector3d n = h.normal.normalized();
  const Eigen::Vector3d w = a.cross(n);
  const Eigen::Vector3d v = p - h.ends[0];
  const double along = v.dot(a), length = (h.ends[1] - h.ends[0]).norm();
  const double out = v.dot(n);
  return along >= -0.02 && along <= length + 0.02 && std::fabs(v.dot(w)) <= 0.026 &&
         out >= -0.075 && out <= 0.025;
}

// A mesh of the given triangles of `from`, with only the vertices they use.
std::shared_ptr<const TriangleMesh> sub_mesh(const TriangleMesh& from,
                                             const std::vector<Eigen::Vector3i>& triangles) {
  std::vector<std::int32_t> remap(from.vertices().size(), -1);
  std::vector<Eigen::Vector3d> vertices;
  std::vector<Eigen::Vector3i> out;
  out.reserve(triangles.size());
  for (const Eigen::Vector3i& tri : triangles) {
    Eigen::Vector3i t;
    for (int k = 0; k < 3; ++k) {
      std::int32_t& to = remap[static_cast<std::size_t>(tri[k])];
      if (to < 0) {
        to = static_cast<std::int32_t>(vertices.size());
        vertices.push_back(from.vertices()[static_cast<std::size_t>(tri[k])]);
      }
      t[k] = to;
    }
    out.push_back(t);
  }
  return std::make_shared<const TriangleMesh>(std::move(vertices), std::move(out));
}

// How deep behind its centre line a handrail's claimed triangles reach
// (the feet's undersides, on the face); the model frame.
double deepest_behind_m(const MeshHandrail& h, const TriangleMesh& whole,
                        const std::vector<Eigen::Vector3i>& triangles) {
  const Eigen::Vector3d n = h.normal.normalized();
  double deepest = 0.0;
  for (const Eigen::Vector3i& tri : triangles) {
    for (int c = 0; c < 3; ++c) {
      const Eigen::Vector3d& v = whole.vertices()[static_cast<std::size_t>(tri[c])];
      deepest = std::max(deepest, -(v - h.ends[0]).dot(n));
    }
  }
  return deepest;
}

}  // namespace

int Scene::add_mesh_handrails(std::size_t mesh_index, const std::vector<MeshHandrail>& rails) {
  if (mesh_index >= meshes.size() || meshes[mesh_index].surface < 0) return rails.empty() ? -1 : 0;
  SceneMesh& m = meshes[mesh_index];
  const TriangleMesh& whole = *m.mesh;
  std::vector<std::vector<Eigen::Vector3i>> claimed(rails.size());
  std::vector<Eigen::Vector3i> rest;
  for (const Eigen::Vector3i& tri : whole.triangles()) {
    std::size_t owner = rails.size();
    for (std::size_t k = 0; k < rails.size() && owner == rails.size(); ++k) {
      bool inside = true;
      for (int c = 0; c < 3 && inside; ++c) {
        inside = in_handrail_box(rails[k], whole.vertices()[static_cast<std::size_t>(tri[c])]);
      }
      if (inside) owner = k;
    }
    if (owner < rails.size()) {
      claimed[owner].push_back(tri);
    } else {
      rest.push_back(tri);
    }
  }
  // Every one checked before the scene changes: each must hold triangles
  // reaching a leg's length behind its centre line (its feet); one with
  // none, or only the bar (its normal points into the wall), is refused.
  std::vector<double> deepest(rails.size());
  for (std::size_t k = 0; k < rails.size(); ++k) {
    deepest[k] = deepest_behind_m(rails[k], whole, claimed[k]);
    if (claimed[k].empty() || deepest[k] < kMeshHandrailMinFootDepthM) {
      return static_cast<int>(k);
    }
  }
  for (std::size_t k = 0; k < rails.size(); ++k) {
    Handrail h{};
    h.kind = HandrailKind::kInModuleMesh;
    h.mesh = sub_mesh(whole, claimed[k]);
    h.normal = (m.R * rails[k].normal).normalized();
    for (int e = 0; e < 2; ++e) h.given_ends[e] = m.R * rails[k].ends[e] + m.t;
    h.axis = (h.given_ends[1] - h.given_ends[0]).normalized();
    h.bar_length_m = (h.given_ends[1] - h.given_ends[0]).norm();
    h.foot_center = 0.5 * (h.given_ends[0] + h.given_ends[1]) - deepest[k] * h.normal;
    h.reflectivity = surfaces[static_cast<std::size_t>(m.surface)].reflectivity;
    Surface s{};
    s.kind = SurfaceKind::kMesh;
    s.object_id = static_cast<std::int32_t>(handrails.size());
    s.reflectivity = h.reflectivity;
    detail::set_mesh_surface(h.mesh, m.R, m.t, &s);
    handrails.push_back(h);
    surfaces.push_back(s);
  }
  m.mesh = sub_mesh(whole, rest);
  detail::set_mesh_surface(m.mesh, m.R, m.t, &surfaces[static_cast<std::size_t>(m.surface)]);
  return -1;
}

}  // namespace sim_hal
