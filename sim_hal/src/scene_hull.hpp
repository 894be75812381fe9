#pragma once
// Shared by the scene's files: a surface's bounds and hull for the
// renderer's cull.
#include <Eigen/Core>
#include <memory>

#include "sim_hal/scene.hpp"

namespace sim_hal::detail {

// The 8 corners of an oriented box (centre, rotation whose columns are the
// box's axes, half sizes) as a surface's hull.
void set_box_hull(const Eigen::Vector3d& center, const Eigen::Matrix3d& R,
                  const Eigen::Vector3d& half, Surface* s);

// A mesh surface: the mesh placed by R, t (world = R * model + t), its
// bounding sphere and its model box as the hull.
void set_mesh_surface(const std::shared_ptr<const TriangleMesh>& mesh, const Eigen::Matrix3d& R,
                      const Eigen::Vector3d& t, Surface* s);

}  // namespace sim_hal::detail
