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
// handrail meshes; kModuleRail the plain box bar on box legs built into the
// modules (about 1 m long); kInModuleMesh a handrail the module's own mesh
// models (Columbus has some three dozen), its surfaces the mesh's triangles.
enum class HandrailKind : std::uint8_t { kPaperRound, kIss, kIssMesh, kModuleRail, kInModuleMesh };
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
  // kInModuleMesh: the module mesh's triangles on this handrail.
  std::shared_ptr<const TriangleMesh> mesh;
  BarExtent mesh_bar{};
  // kInModuleMesh only: the centre line's ends, world frame (end 0 at
  // -axis), as the module's survey gives them.
  Eigen::Vector3d given_ends[2] = {Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()};
  // Centre-line geometry per kind (the estimator's geometry config agrees,
  // except for kModuleRail, which it has no kind for).
  double center_offset_m() const;
  Eigen::Vector3d end_point(int end) const;  // centre line, end 0 at -axis
};

// A rectangle in a rack wall's own coordinates (metres): u from u0 to u1,
// v from v0 to v1.
struct WallRect {
  double u0 = 0.0, u1 = 0.0, v0 = 0.0, v1 = 0.0;
  double width_m() const { return u1 - u0; }
  double height_m() const { return v1 - v0; }
};

// A wall, deck or overhead of ISS racks. Its frame: `center` on the
// reference plane, `normal` toward the room, v along `up` (projected onto
// the plane), u = v x normal (as for a plain wall). A depth is a distance
// along the normal from the reference plane: positive stands proud,
// negative is recessed.
struct RackWall {
  Eigen::Vector3d center = Eigen::Vector3d::Zero(), normal = Eigen::Vector3d::UnitX();
  Eigen::Vector3d up = Eigen::Vector3d::UnitZ();
  // How far back the racks reach: each face is a box from here to its
  // depth, so a step between faces and the sides of a gap have walls.
  double back_depth_m = -0.40;
  struct Face {
    WallRect rect;
    double depth_m = 0.0;
    double reflectivity = 0.6;
  };
  // A strip about 2.6 cm wide and 1.3 cm proud along a rack edge, on the
  // surface at base_depth_m (the face it sits on); handrails stand on it.
  struct SeatTrack {
    Eigen::Vector2d from = Eigen::Vector2d::Zero(), to = Eigen::Vector2d::Zero();  // (u, v)
    double base_depth_m = 0.0, width_m = 0.026, height_m = 0.013;
    double reflectivity = 0.5;
    double top_depth_m() const { return base_depth_m + height_m; }
  };
  // Where no face is: a gap between racks or an empty bay. With a back, a
  // surface at depth_m; without, the ray goes on (an opening that returns
  // nothing). With side walls, four walls from depth_m up to rim_depth_m
  // (a bay's box recess, where no neighbouring face provides them).
  struct Recess {
    WallRect rect;
    bool has_back = true;
    double depth_m = -0.12;
    bool side_walls = false;
    double rim_depth_m = 0.0;
    double reflectivity = 0.3;
  };
  // A small raised rectangle of its own reflectivity (edge strips, lights,
  // labels): from base_depth_m to base_depth_m + height_m.
  struct Strip {
    WallRect rect;
    double base_depth_m = 0.0, height_m = 0.003;
    double reflectivity = 0.8;
  };
  std::vector<Face> faces;
  std::vector<SeatTrack> seat_tracks;
  std::vector<Recess> recesses;
  std::vector<Strip> strips;

  Eigen::Vector3d unit_normal() const;
  Eigen::Vector3d unit_u() const;
  Eigen::Vector3d unit_v() const;
  // A point given in the wall's coordinates, in the world.
  Eigen::Vector3d point(double u_m, double v_m, double depth_m) const;
};

// A triangle mesh placed in the scene as clutter or structure (an ISS module
// interior): world = R * model + t.
struct SceneMesh {
  std::string path;
  std::shared_ptr<const TriangleMesh> mesh;
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  Eigen::Vector3d t = Eigen::Vector3d::Zero();
  std::int32_t surface = -1;  // its entry in Scene::surfaces (set by add_mesh)
};

// A handrail that a mesh models itself, in the mesh's own frame: its
// centre line's ends (from the outer side of one leg to the outer side of
// the other) and the normal of the face it stands on, toward the room
// (sim_hal/scenarios/mesh_handrails.py finds them in a module mesh).
// A modelled handrail's legs and feet reach at least this far behind its
// centre line (an ISS handrail's centre line is 6.1 to 6.3 cm off its face;
// Columbus's lowest, on the aft cone, 3.1 cm); its bar alone, half its
// depth (1.5 cm), which is all a box turned the wrong way round holds.
constexpr double kMeshHandrailMinFootDepthM = 0.025;
struct MeshHandrail {
  Eigen::Vector3d ends[2] = {Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()};
  Eigen::Vector3d normal = Eigen::Vector3d::UnitX();
};

struct Scene {
  std::vector<Surface> surfaces;
  std::vector<Handrail> handrails;
  // What the scene was built from beyond plain surfaces (evaluation reports
  // by surface kind; the meshes are owned here).
  std::vector<RackWall> rack_walls;
  std::vector<SceneMesh> meshes;

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
  // A bounded plane: `u` and `v` unit and perpendicular to `normal`.
  void add_rect(const Eigen::Vector3d& center, const Eigen::Vector3d& normal,
                const Eigen::Vector3d& u, const Eigen::Vector3d& v, double half_u_m,
                double half_v_m, double reflectivity);
  // The faces as boxes, the tracks and strips as boxes, the recesses'
  // backs and side walls as rectangles.
  void add_rack_wall(const RackWall& wall);
  void add_mesh(const SceneMesh& mesh, double reflectivity = 0.5);
  // Makes the handrails that meshes[mesh_index] models handrails of the
  // scene (kInModuleMesh, after those already added): the mesh's triangles
  // lying wholly in a handrail's box (its centre line +-2 cm along, 2.6 cm
  // either side across, 7.5 cm behind to 2.5 cm in front of it: the bar,
  // legs, feet and plates) become that handrail's own surface, so that
  // ground truth sees it; the rest stay the module's. What the camera sees
  // does not change. Each must hold triangles reaching at least
  // kMeshHandrailMinFootDepthM behind its centre line (its legs and feet):
  // returns the index in `handrails` (the argument) of the first that does
  // not (its ends are wrong, or its normal points into the wall), with the
  // scene unchanged; 0 when meshes[mesh_index] was not added by add_mesh;
  // -1 when all were added.
  int add_mesh_handrails(std::size_t mesh_index, const std::vector<MeshHandrail>& handrails);
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
