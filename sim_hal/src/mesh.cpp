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

// Slab test: does the ray pass through the box between t_min and t_max?
// *entry_t is where it enters (t_min if it starts inside). Branch-free:
// which slab bounds last is a coin toss for the predictor. A NaN (0 * inf,
// a ray in a slab's plane) compares false and narrows nothing.
bool hits_box(const float* lo, const float* hi, const Eigen::Vector3f& o,
              const Eigen::Vector3f& inv_d, float t_min, float t_max, float* entry_t) {
  float t0 = t_min, t1 = t_max;
  for (int a = 0; a < 3; ++a) {
    const float ta = (lo[a] - o[a]) * inv_d[a], tb = (hi[a] - o[a]) * inv_d[a];
    const float near_t = ta < tb ? ta : tb, far_t = ta < tb ? tb : ta;
    t0 = near_t > t0 ? near_t : t0;
    t1 = far_t < t1 ? far_t : t1;
  }
  *entry_t = t0;
  return t0 <= t1;
}

// Moller-Trumbore; two-sided. The model's vertices are single precision
// in the file, so float loses nothing here.
bool hit_triangle(const float* a, const float* e1_in, const float* e2_in, const Eigen::Vector3f& o,
                  const Eigen::Vector3f& d, float* t) {
  const Eigen::Map<const Eigen::Vector3f> e1(e1_in), e2(e2_in), corner(a);
  const Eigen::Vector3f p = d.cross(e2);
  const float det = e1.dot(p);
  if (std::fabs(det) < 1e-12f) return false;
  const float inv = 1.0f / det;
  const Eigen::Vector3f s = o - corner;
  const float u = s.dot(p) * inv;
  if (u < 0.0f || u > 1.0f) return false;
  const Eigen::Vector3f q = s.cross(e1);
  const float v = d.dot(q) * inv;
  if (v < 0.0f || u + v > 1.0f) return false;
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
  // The copies a ray walks: boxes and triangles in single precision, each
  // triangle as a corner and two edges in the hierarchy's order.
  flat_nodes_.reserve(nodes_.size());
  for (const Node& node : nodes_) {
    FlatNode f{};
    for (int a = 0; a < 3; ++a) {
      f.lo[a] = static_cast<float>(node.lo[a]);
      f.hi[a] = static_cast<float>(node.hi[a]);
    }
    f.first = node.first;
    f.count = node.count;
    flat_nodes_.push_back(f);
  }
  // The double-precision nodes were the build's work space only.
  std::vector<Node>().swap(nodes_);
  flat_triangles_.reserve(triangles_.size());
  for (const Eigen::Vector3i& tri : triangles_) {
    const Eigen::Vector3d& a = vertices_[static_cast<std::size_t>(tri[0])];
    const Eigen::Vector3d e1 = vertices_[static_cast<std::size_t>(tri[1])] - a;
    const Eigen::Vector3d e2 = vertices_[static_cast<std::size_t>(tri[2])] - a;
    FlatTriangle f{};
    for (int k = 0; k < 3; ++k) {
      f.corner[k] = static_cast<float>(a[k]);
      f.e1[k] = static_cast<float>(e1[k]);
      f.e2[k] = static_cast<float>(e2[k]);
    }
    flat_triangles_.push_back(f);
  }
}

namespace {

double half_area(const Eigen::AlignedBox3d& box) {
  if (box.isEmpty()) return 0.0;
  const Eigen::Vector3d e = box.sizes();
  return e.x() * e.y() + e.y() * e.z() + e.z() * e.x();
}

}  // namespace

// Reorders the triangles [begin, end) into two groups and returns where the
// second starts. The binned surface-area heuristic: a ray's chance of
// entering a child's box goes with the box's surface area, so the split
// with the least (area x triangles) summed over both children costs rays
// the fewest box and triangle tests. (A median split of a handrail's long,
// curved bar left sibling boxes overlapping along most of it, and rays
// opened both.) Candidate planes: kBins bins of the centroids' extent on
// each axis. Falls back to the median when the centroids share one bin.
std::int32_t TriangleMesh::split_by_surface_area(std::int32_t begin, std::int32_t end,
                                                 const Eigen::Vector3d& centroid_lo,
                                                 const Eigen::Vector3d& centroid_hi) {
  constexpr int kBins = 16;
  auto centroid = [&](const Eigen::Vector3i& tri) {
    return (vertices_[static_cast<std::size_t>(tri[0])] +
            vertices_[static_cast<std::size_t>(tri[1])] +
            vertices_[static_cast<std::size_t>(tri[2])]) /
           3.0;
  };
  const Eigen::Vector3d extent = centroid_hi - centroid_lo;
  auto bin_of = [&](const Eigen::Vector3i& tri, int axis) {
    const double f = (centroid(tri)[axis] - centroid_lo[axis]) / extent[axis];
    return std::clamp(static_cast<int>(f * kBins), 0, kBins - 1);
  };
  double best_cost = INFINITY;
  int best_axis = -1, best_bin = 0;
  for (int axis = 0; axis < 3; ++axis) {
    if (!(extent[axis] > 0.0)) continue;
    Eigen::AlignedBox3d boxes[kBins];
    int counts[kBins] = {};
    for (std::int32_t k = begin; k < end; ++k) {
      const Eigen::Vector3i& tri = triangles_[static_cast<std::size_t>(k)];
      const int b = bin_of(tri, axis);
      for (int j = 0; j < 3; ++j) boxes[b].extend(vertices_[static_cast<std::size_t>(tri[j])]);
      ++counts[b];
    }
    // Cost of cutting after bin b: sweep from the left, then the right.
    double left_cost[kBins];
    Eigen::AlignedBox3d left;
    int left_count = 0;
    for (int b = 0; b < kBins - 1; ++b) {
      left.extend(boxes[b]);
      left_count += counts[b];
      left_cost[b] = left_count * half_area(left);
    }
    Eigen::AlignedBox3d right;
    int right_count = 0;
    for (int b = kBins - 1; b > 0; --b) {
      right.extend(boxes[b]);
      right_count += counts[b];
      const int left_n = (end - begin) - right_count;
      if (left_n == 0 || right_count == 0) continue;
      const double cost = left_cost[b - 1] + right_count * half_area(right);
      if (cost < best_cost) {
        best_cost = cost;
        best_axis = axis;
        best_bin = b - 1;
      }
    }
  }
  if (best_axis < 0) {
    const std::int32_t mid = begin + (end - begin) / 2;
    std::nth_element(triangles_.begin() + begin, triangles_.begin() + mid, triangles_.begin() + end,
                     [&](const Eigen::Vector3i& a, const Eigen::Vector3i& b) {
                       return centroid(a).x() < centroid(b).x();
                     });
    return mid;
  }
  const auto second = std::partition(
      triangles_.begin() + begin, triangles_.begin() + end,
      [&](const Eigen::Vector3i& tri) { return bin_of(tri, best_axis) <= best_bin; });
  return static_cast<std::int32_t>(second - triangles_.begin());
}

// Node `index` gets the triangles [begin, end): a leaf when few, else two
// adjacent children split by split_by_surface_area.
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
  const std::int32_t mid = split_by_surface_area(begin, end, clo, chi);
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
  float t = 0.0f;
  Eigen::Vector3f normal;
  if (!intersect(o.cast<float>(), d.cast<float>(), static_cast<float>(t_min),
                 static_cast<float>(std::min(t_max, 1e30)), &t, &normal)) {
    return false;
  }
  hit->t = t;
  hit->normal = normal.cast<double>();
  return true;
}

bool TriangleMesh::intersect(const Eigen::Vector3f& o, const Eigen::Vector3f& d, float t_min,
                             float t_max, float* t_hit, Eigen::Vector3f* normal) const {
  if (flat_nodes_.empty()) return false;
  const Eigen::Vector3f inv_d(1.0f / d.x(), 1.0f / d.y(), 1.0f / d.z());
  // Nearer child first, each node kept with where the ray enters its box:
  // once a triangle is hit, boxes entered beyond it are skipped unopened.
  struct Pending {
    std::int32_t node;
    float entry_t;
  };
  Pending stack[2 * kMaxDepth + 2];
  int top = 0;
  float best = t_max, entry = 0.0f;
  if (!hits_box(flat_nodes_[0].lo, flat_nodes_[0].hi, o, inv_d, t_min, best, &entry)) return false;
  stack[top++] = {0, entry};
  std::int32_t best_tri = -1;
  while (top > 0) {
    const Pending pending = stack[--top];
    if (pending.entry_t >= best) continue;
    const FlatNode& node = flat_nodes_[static_cast<std::size_t>(pending.node)];
    if (node.count > 0) {
      for (std::int32_t k = node.first; k < node.first + node.count; ++k) {
        const FlatTriangle& tri = flat_triangles_[static_cast<std::size_t>(k)];
        float t = 0.0f;
        if (hit_triangle(tri.corner, tri.e1, tri.e2, o, d, &t) && t > t_min && t < best) {
          best = t;
          best_tri = k;
        }
      }
      continue;
    }
    const std::int32_t a = node.first, b = node.first + 1;
    const FlatNode& node_a = flat_nodes_[static_cast<std::size_t>(a)];
    const FlatNode& node_b = flat_nodes_[static_cast<std::size_t>(b)];
    float entry_a = 0.0f, entry_b = 0.0f;
    const bool hit_a = hits_box(node_a.lo, node_a.hi, o, inv_d, t_min, best, &entry_a);
    const bool hit_b = hits_box(node_b.lo, node_b.hi, o, inv_d, t_min, best, &entry_b);
    if (hit_a && hit_b) {
      // The farther goes on the stack first, so the nearer is opened next.
      const bool a_first = entry_a <= entry_b;
      stack[top++] = a_first ? Pending{b, entry_b} : Pending{a, entry_a};
      stack[top++] = a_first ? Pending{a, entry_a} : Pending{b, entry_b};
    } else if (hit_a) {
      stack[top++] = {a, entry_a};
    } else if (hit_b) {
      stack[top++] = {b, entry_b};
    }
  }
  if (best_tri < 0) return false;
  const FlatTriangle& tri = flat_triangles_[static_cast<std::size_t>(best_tri)];
  *t_hit = best;
  *normal = Eigen::Map<const Eigen::Vector3f>(tri.e1)
                .cross(Eigen::Map<const Eigen::Vector3f>(tri.e2))
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
