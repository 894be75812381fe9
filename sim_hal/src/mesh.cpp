#include "sim_hal/mesh.hpp"

#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <Eigen/Geometry>

#include <algorithm>
#include <assimp/Importer.hpp>
#include <cmath>

namespace sim_hal {
namespace {

constexpr int kLeafTriangles = 4;
constexpr int kMaxDepth = 40;

// Slab test: does the ray enter the box before t_max (and after t_min)?
bool hits_box(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, const Eigen::Vector3d& o,
              const Eigen::Vector3d& inv_d, double t_min, double t_max) {
  double t0 = t_min, t1 = t_max;
  for (int a = 0; a < 3; ++a) {
    double near_t = (lo[a] - o[a]) * inv_d[a], far_t = (hi[a] - o[a]) * inv_d[a];
    if (near_t > far_t) std::swap(near_t, far_t);
    // NaN (0 * inf, a ray in the slab's plane) compares false: no narrowing.
    if (near_t > t0) t0 = near_t;
    if (far_t < t1) t1 = far_t;
    if (t0 > t1) return false;
  }
  return true;
}

// Moller-Trumbore; two-sided.
bool hit_triangle(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                  const Eigen::Vector3d& o, const Eigen::Vector3d& d, double* t) {
  const Eigen::Vector3d e1 = b - a, e2 = c - a;
  const Eigen::Vector3d p = d.cross(e2);
  const double det = e1.dot(p);
  if (std::fabs(det) < 1e-14) return false;
  const double inv = 1.0 / det;
  const Eigen::Vector3d s = o - a;
  const double u = s.dot(p) * inv;
  if (u < 0.0 || u > 1.0) return false;
  const Eigen::Vector3d q = s.cross(e1);
  const double v = d.dot(q) * inv;
  if (v < 0.0 || u + v > 1.0) return false;
  *t = e2.dot(q) * inv;
  return true;
}

}  // namespace

TriangleMesh::TriangleMesh(std::vector<Eigen::Vector3d> vertices,
                           std::vector<Eigen::Vector3i> triangles)
    : vertices_(std::move(vertices)) {
  for (const Eigen::Vector3i& tri : triangles) {
    const Eigen::Vector3d& a = vertices_[static_cast<std::size_t>(tri[0])];
    const Eigen::Vector3d& b = vertices_[static_cast<std::size_t>(tri[1])];
    const Eigen::Vector3d& c = vertices_[static_cast<std::size_t>(tri[2])];
    if ((b - a).cross(c - a).norm() > 1e-14) triangles_.push_back(tri);
  }
  if (triangles_.empty()) return;
  nodes_.reserve(2 * triangles_.size() / kLeafTriangles + 2);
  nodes_.emplace_back();
  build(0, 0, static_cast<std::int32_t>(triangles_.size()), 0);
  lo_ = nodes_[0].lo;
  hi_ = nodes_[0].hi;
}

// Node `index` gets the triangles [begin, end): a leaf when few, else split
// at the median of their centroids along the widest axis of the centroids'
// bounds into two adjacent children.
void TriangleMesh::build(std::int32_t index, std::int32_t begin, std::int32_t end, int depth) {
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(INFINITY), hi = -lo;
  Eigen::Vector3d clo = lo, chi = hi;
  auto centroid = [&](const Eigen::Vector3i& tri) {
    return (vertices_[static_cast<std::size_t>(tri[0])] +
            vertices_[static_cast<std::size_t>(tri[1])] +
            vertices_[static_cast<std::size_t>(tri[2])]) /
           3.0;
  };
  for (std::int32_t k = begin; k < end; ++k) {
    const Eigen::Vector3i& tri = triangles_[static_cast<std::size_t>(k)];
    for (int j = 0; j < 3; ++j) {
      lo = lo.cwiseMin(vertices_[static_cast<std::size_t>(tri[j])]);
      hi = hi.cwiseMax(vertices_[static_cast<std::size_t>(tri[j])]);
    }
    const Eigen::Vector3d c = centroid(tri);
    clo = clo.cwiseMin(c);
    chi = chi.cwiseMax(c);
  }
  Node node;
  node.lo = lo;
  node.hi = hi;
  if (end - begin <= kLeafTriangles || depth >= kMaxDepth) {
    node.first = begin;
    node.count = end - begin;
    nodes_[static_cast<std::size_t>(index)] = node;
    return;
  }
  int axis = 0;
  const Eigen::Vector3d extent = chi - clo;
  if (extent.y() > extent[axis]) axis = 1;
  if (extent.z() > extent[axis]) axis = 2;
  const std::int32_t mid = begin + (end - begin) / 2;
  std::nth_element(triangles_.begin() + begin, triangles_.begin() + mid, triangles_.begin() + end,
                   [&](const Eigen::Vector3i& a, const Eigen::Vector3i& b) {
                     return centroid(a)[axis] < centroid(b)[axis];
                   });
  node.first = static_cast<std::int32_t>(nodes_.size());
  node.count = 0;
  nodes_[static_cast<std::size_t>(index)] = node;
  nodes_.emplace_back();
  nodes_.emplace_back();
  build(node.first, begin, mid, depth + 1);
  build(node.first + 1, mid, end, depth + 1);
}

bool TriangleMesh::intersect(const Eigen::Vector3d& o, const Eigen::Vector3d& d, double t_min,
                             double t_max, MeshHit* hit) const {
  if (nodes_.empty()) return false;
  const Eigen::Vector3d inv_d(1.0 / d.x(), 1.0 / d.y(), 1.0 / d.z());
  std::int32_t stack[2 * kMaxDepth + 2];
  int top = 0;
  stack[top++] = 0;
  double best = t_max;
  std::int32_t best_tri = -1;
  while (top > 0) {
    const Node& node = nodes_[static_cast<std::size_t>(stack[--top])];
    if (!hits_box(node.lo, node.hi, o, inv_d, t_min, best)) continue;
    if (node.count > 0) {
      for (std::int32_t k = node.first; k < node.first + node.count; ++k) {
        const Eigen::Vector3i& tri = triangles_[static_cast<std::size_t>(k)];
        double t = 0.0;
        if (hit_triangle(vertices_[static_cast<std::size_t>(tri[0])],
                         vertices_[static_cast<std::size_t>(tri[1])],
                         vertices_[static_cast<std::size_t>(tri[2])], o, d, &t) &&
            t > t_min && t < best) {
          best = t;
          best_tri = k;
        }
      }
      continue;
    }
    stack[top++] = node.first;
    stack[top++] = node.first + 1;
  }
  if (best_tri < 0) return false;
  const Eigen::Vector3i& tri = triangles_[static_cast<std::size_t>(best_tri)];
  const Eigen::Vector3d& a = vertices_[static_cast<std::size_t>(tri[0])];
  hit->t = best;
  hit->normal = (vertices_[static_cast<std::size_t>(tri[1])] - a)
                    .cross(vertices_[static_cast<std::size_t>(tri[2])] - a)
                    .normalized();
  return true;
}

bool load_collada_mesh(const std::string& path, std::vector<Eigen::Vector3d>* vertices,
                       std::vector<Eigen::Vector3i>* triangles, std::string* error) {
  Assimp::Importer importer;
  // The handrail files declare Z up; assimp would turn them Y up.
  importer.SetPropertyBool(AI_CONFIG_IMPORT_COLLADA_IGNORE_UP_DIRECTION, true);
  const aiScene* scene =
      importer.ReadFile(path, aiProcess_Triangulate | aiProcess_PreTransformVertices |
                                  aiProcess_JoinIdenticalVertices | aiProcess_SortByPType);
  if (scene == nullptr) {
    *error = path + ": cannot load mesh: " + importer.GetErrorString();
    return false;
  }
  vertices->clear();
  triangles->clear();
  for (unsigned m = 0; m < scene->mNumMeshes; ++m) {
    const aiMesh* mesh = scene->mMeshes[m];
    const int base = static_cast<int>(vertices->size());
    for (unsigned v = 0; v < mesh->mNumVertices; ++v) {
      const aiVector3D& p = mesh->mVertices[v];
      vertices->emplace_back(p.x, p.y, p.z);
    }
    for (unsigned f = 0; f < mesh->mNumFaces; ++f) {
      const aiFace& face = mesh->mFaces[f];
      if (face.mNumIndices != 3) continue;  // points and lines
      triangles->emplace_back(base + static_cast<int>(face.mIndices[0]),
                              base + static_cast<int>(face.mIndices[1]),
                              base + static_cast<int>(face.mIndices[2]));
    }
  }
  if (triangles->empty()) {
    *error = path + ": the file holds no triangles";
    return false;
  }
  return true;
}

BarExtent measure_bar(const TriangleMesh& mesh, double min_height_m) {
  BarExtent bar;
  // Along the rail: the vertices above the legs' tops belong to the bar.
  bar.z_min = INFINITY;
  bar.z_max = -INFINITY;
  for (const Eigen::Vector3d& v : mesh.vertices()) {
    if (v.x() <= min_height_m) continue;
    bar.z_min = std::min(bar.z_min, v.z());
    bar.z_max = std::max(bar.z_max, v.z());
  }
  // Across it: probe the cross-section half way along, where only the bar
  // is (an extruded bar has no vertices there to read).
  const double z_mid = 0.5 * (bar.z_min + bar.z_max);
  MeshHit hit;
  const double far = 1.0;
  if (mesh.intersect({far, 0.0, z_mid}, {-1.0, 0.0, 0.0}, 0.0, 2.0 * far, &hit)) {
    bar.x_max = far - hit.t;
  }
  if (mesh.intersect({1e-4, 0.0, z_mid}, {1.0, 0.0, 0.0}, 0.0, far, &hit)) {
    bar.x_min = 1e-4 + hit.t;
  }
  const double x_mid = bar.center_offset_m();
  if (mesh.intersect({x_mid, far, z_mid}, {0.0, -1.0, 0.0}, 0.0, 2.0 * far, &hit)) {
    bar.y_max = far - hit.t;
  }
  if (mesh.intersect({x_mid, -far, z_mid}, {0.0, 1.0, 0.0}, 0.0, 2.0 * far, &hit)) {
    bar.y_min = -far + hit.t;
  }
  return bar;
}

}  // namespace sim_hal
