#pragma once
// What the simulated camera sees, in metres, in a world frame of the
// scenario's choosing. Surfaces are analytic so a ray finds its exact hit.
#include <Eigen/Core>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "sim_hal/mesh.hpp"

namespace sim_hal {

// kIss is the analytic rounded-rectangle bar; kIssMesh one of the real
// handrail meshes.
enum class HandrailKind : std::uint8_t { kPaperRound, kIss, kIssMesh };
const char* to_string(HandrailKind kind);

// A bounded plane: centre, unit normal, in-plane unit axes u and v, half
// sizes along them.
struct RectSurface {
  Eigen::Vector3d center = Eigen::Vector3d::Zero(), normal = Eigen::Vector3d::UnitZ();
  Eigen::Vector3d u = Eigen::Vector3d::UnitX(), v = Eigen::Vector3d::UnitY();
  double half_u = 0.0, half_v = 0.0;
};

// A finite cylinder with flat caps.
struct CylinderSurface {
  Eigen::Vector3d center = Eigen::Vector3d::Zero(), axis = Eigen::Vector3d::UnitZ();  // axis unit
  double radius = 0.0, half_length = 0.0;
};

// An oriented box: centre, rotation (columns = box axes), half sizes.
struct BoxSurface {
  Eigen::Vector3d center = Eigen::Vector3d::Zero();
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  Eigen::Vector3d half = Eigen::Vector3d::Zero();
};

// A bar whose cross-section is a rounded rectangle (the ISS handrail),
// extruded along `axis`; `depth_dir` is the cross-section's long side.
struct RoundedBarSurface {
  Eigen::Vector3d center = Eigen::Vector3d::Zero(), axis = Eigen::Vector3d::UnitZ();
  Eigen::Vector3d depth_dir = Eigen::Vector3d::UnitX();
  double half_depth = 0.0, half_width = 0.0, corner_radius = 0.0, half_length = 0.0;
};

// A triangle mesh placed in the world: world = R * model + t.
struct MeshSurface {
  const TriangleMesh* mesh = nullptr;  // owned by the handrail that placed it
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  Eigen::Vector3d t = Eigen::Vector3d::Zero();
};

enum class SurfaceKind : std::uint8_t { kRect, kCylinder, kBox, kRoundedBar, kMesh };

struct Surface {
  SurfaceKind kind = SurfaceKind::kRect;
  std::int32_t object_id = -1;  // handrail index for handrail parts, -1 otherwise
  double reflectivity = 0.5;    // 0..1
  RectSurface rect{};
  CylinderSurface cylinder{};
  BoxSurface box{};
  RoundedBarSurface bar{};
  MeshSurface mesh{};
  // Bounding sphere for a quick reject.
  Eigen::Vector3d bound_center = Eigen::Vector3d::Zero();
  double bound_radius = 0.0;
  // A tighter bound for the renderer's per-tile cull: the convex hull of
  // spheres of radius hull_radius around the first hull_points points
  // (a rectangle's corners, a cylinder's cap centres, a box's corners, a
  // capsule along a mesh handrail).
  Eigen::Vector3d hull[8];
  int hull_points = 0;
  double hull_radius = 0.0;
};

// A handrail as placed on a wall: its footprint centre on the wall, the
// wall's unit normal, and the bar's direction.
struct Handrail {
  HandrailKind kind = HandrailKind::kIss;
  Eigen::Vector3d foot_center = Eigen::Vector3d::Zero(), normal = Eigen::Vector3d::UnitX();
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();
  double bar_length_m = 0.55;  // for kIssMesh: measured from the mesh
  double reflectivity = 0.5;
  // kIssMesh only: the model (frame: x out of the wall, z along the rail,
  // origin on the wall at the footprint's centre) and its bar as measured.
  std::shared_ptr<const TriangleMesh> mesh;
  BarExtent mesh_bar{};
  // Centre-line geometry per kind (the estimator's geometry config agrees).
  double center_offset_m() const;
  Eigen::Vector3d end_point(int end) const;  // centre line, end 0 at -axis
};

struct Scene {
  std::vector<Surface> surfaces;
  std::vector<Handrail> handrails;

  void add_wall(const Eigen::Vector3d& center, const Eigen::Vector3d& normal,
                const Eigen::Vector3d& up, double width_m, double height_m,
                double reflectivity = 0.6);
  // Adds the bar and its two legs as surfaces.
  void add_handrail(const Handrail& handrail);
  // A cable or pipe through a polyline: one cylinder per segment.
  void add_cable(const std::vector<Eigen::Vector3d>& points, double diameter_m,
                 double reflectivity = 0.3);
  void add_box(const Eigen::Vector3d& center, const Eigen::Matrix3d& R,
               const Eigen::Vector3d& size_m, double reflectivity = 0.5);
};

struct Hit {
  double t = 0.0;                                    // along the ray
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();  // unit, facing the ray
  std::int32_t surface = -1;
};

// Nearest hit along origin + t * dir (dir unit) with t in (t_min, t_max),
// in double precision over every surface: the reference (ground truth's
// occlusion test; the renderer's own ray casting, view_surfaces.hpp, is
// checked against it).
bool intersect_scene(const Scene& scene, const Eigen::Vector3d& origin, const Eigen::Vector3d& dir,
                     double t_min, double t_max, Hit* hit);

}  // namespace sim_hal
