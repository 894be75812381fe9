#pragma once
// The scene's surfaces as one camera sees them, set up for casting every
// pixel's ray from the camera centre. Each surface gets its own local frame
// (the frame in which its test is axis-aligned: a wall's normal, a box's
// axes, a cylinder's axis), expressed from the camera frame, in single
// precision, with everything that depends only on the ray's origin worked
// out once per frame. A ray then costs one 3 x 3 rotation and a few
// comparisons per surface instead of double-precision vector algebra.
//
// `intersect_scene` (scene.hpp) stays the double-precision reference for
// rays from anywhere; test_sim_camera checks the two agree.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <vector>

#include "sim_hal/scene.hpp"

namespace sim_hal {

struct ViewSurface {
  SurfaceKind kind = SurfaceKind::kRect;
  std::int32_t scene_index = -1;
  float reflectivity = 0.5f;
  // Bounding sphere in the camera frame, for a quick reject.
  Eigen::Vector3f bound_center = Eigen::Vector3f::Zero();
  float bound_radius = 0.0f, bound_center_sq_m2 = 0.0f;
  // p_local = R_local_cam * p_cam + origin_local: origin_local is where the
  // camera centre sits in the surface's frame.
  Eigen::Matrix3f R_local_cam = Eigen::Matrix3f::Identity();
  Eigen::Vector3f origin_local = Eigen::Vector3f::Zero();
  // Sizes in the local frame, by kind:
  //   rect:        plane x = 0, |y| <= half[1], |z| <= half[2]
  //   box:         |x|, |y|, |z| <= half
  //   cylinder:    axis along x, |x| <= half[0], radius
  //   rounded bar: depth along x (half[0]), width along y (half[1]),
  //                length along z (half[2]), corner radius = radius
  //   mesh:        the model's axes, origin at the centre of its box
  //                (model = local + mesh_box_center), box half sizes
  float half[3] = {0.0f, 0.0f, 0.0f};
  float radius = 0.0f;
  const TriangleMesh* mesh = nullptr;
  Eigen::Vector3f mesh_box_center = Eigen::Vector3f::Zero();
};

struct ViewHit {
  float t_m = 0.0f;            // along the unit ray
  float cos_incidence = 0.0f;  // |surface normal . ray|
  std::int32_t surface = -1;   // index into Scene::surfaces
};

// Places every surface of `scene` in the frame of a camera at T_world_cam.
// `out` is resized to the scene's surface count (no allocation once it has
// held that many).
void place_surfaces_in_view(const Scene& scene, const Eigen::Isometry3d& T_world_cam,
                            std::vector<ViewSurface>* out);

// Nearest hit of the ray t * dir_cam (dir_cam unit, from the camera centre)
// with t in (t_min, t_max), testing the listed surfaces.
bool intersect_view(const ViewSurface* surfaces, const std::int32_t* ids, std::size_t count,
                    const Eigen::Vector3f& dir_cam, float t_min_m, float t_max_m, ViewHit* hit);

}  // namespace sim_hal
