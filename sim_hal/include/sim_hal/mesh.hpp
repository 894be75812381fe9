#pragma once
// Triangle meshes for the simulator: the real ISS handrail models, loaded
// from COLLADA with assimp, and a bounding volume hierarchy so that a ray
// costs a few dozen box tests instead of one test per triangle.
#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

namespace sim_hal {

struct MeshHit {
  double t = 0.0;
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();  // unit, model frame, not yet facing the ray
};

class TriangleMesh {
 public:
  // Takes the triangles (vertex indices into `vertices`) and builds the
  // hierarchy. Degenerate triangles are dropped.
  TriangleMesh(std::vector<Eigen::Vector3d> vertices, std::vector<Eigen::Vector3i> triangles);

  // Nearest hit along o + t d (model frame) with t in (t_min, t_max). The
  // walk is in single precision (the model files hold floats).
  bool intersect(const Eigen::Vector3d& o, const Eigen::Vector3d& d, double t_min, double t_max,
                 MeshHit* hit) const;
  // The same for the renderer: `normal` unit, model frame, not yet facing
  // the ray.
  bool intersect(const Eigen::Vector3f& o, const Eigen::Vector3f& d, float t_min, float t_max,
                 float* t, Eigen::Vector3f* normal) const;

  const std::vector<Eigen::Vector3d>& vertices() const { return vertices_; }
  // The triangles kept (degenerate ones dropped), in the hierarchy's order.
  const std::vector<Eigen::Vector3i>& triangles() const { return triangles_; }
  std::size_t triangle_count() const { return triangles_.size(); }
  Eigen::Vector3d min_corner() const { return lo_; }
  Eigen::Vector3d max_corner() const { return hi_; }

 private:
  struct Node {
    Eigen::Vector3d lo, hi;
    std::int32_t first = 0;  // leaf: first triangle; inner: left child (right = first + 1)
    std::int32_t count = 0;  // triangles in a leaf; 0 for an inner node
  };
  void build(std::int32_t index, std::int32_t begin, std::int32_t end, int depth);
  std::int32_t split_by_surface_area(std::int32_t begin, std::int32_t end,
                                     const Eigen::Vector3d& centroid_lo,
                                     const Eigen::Vector3d& centroid_hi);

  std::vector<Eigen::Vector3d> vertices_;
  std::vector<Eigen::Vector3i> triangles_;
  std::vector<Node> nodes_;  // the build's work space, emptied once flattened
  // What intersect() walks: the nodes and triangles (in the hierarchy's
  // order, as a corner and two edges) in single precision.
  struct FlatNode {
    float lo[3], hi[3];
    std::int32_t first, count;
  };
  struct FlatTriangle {
    float corner[3], e1[3], e2[3];
  };
  std::vector<FlatNode> flat_nodes_;
  std::vector<FlatTriangle> flat_triangles_;
  Eigen::Vector3d lo_ = Eigen::Vector3d::Zero(), hi_ = Eigen::Vector3d::Zero();
};

// Loads every triangle of a COLLADA file, node transforms applied, in the
// file's own axes (its up-axis declaration is ignored, so a Z-up model
// stays Z-up), metres. False with *error naming the file and the problem.
bool load_collada_mesh(const std::string& path, std::vector<Eigen::Vector3d>* vertices,
                       std::vector<Eigen::Vector3i>* triangles, std::string* error);

// The bar of an ISS handrail model (model frame: x = out of the wall,
// z = along the rail, origin on the wall): the extent of the vertices
// standing off the wall by more than `min_height_m`, i.e. above the legs'
// feet and mounting plates. Its centre line runs at the middle of that
// extent in x and y, from z_min to z_max.
struct BarExtent {
  double x_min = 0.0, x_max = 0.0, y_min = 0.0, y_max = 0.0, z_min = 0.0, z_max = 0.0;
  double center_offset_m() const { return 0.5 * (x_min + x_max); }
  double length_m() const { return z_max - z_min; }
};
BarExtent measure_bar(const TriangleMesh& mesh, double min_height_m);

}  // namespace sim_hal
