#pragma once
// Shared by the scene's files: a surface's hull for the renderer's cull.
#include <Eigen/Core>

#include "sim_hal/scene.hpp"

namespace sim_hal::detail {

// The 8 corners of an oriented box (centre, rotation whose columns are the
// box's axes, half sizes) as a surface's hull.
void set_box_hull(const Eigen::Vector3d& center, const Eigen::Matrix3d& R,
                  const Eigen::Vector3d& half, Surface* s);

}  // namespace sim_hal::detail
