#pragma once
// The simulated Pico Flexx's optics: a pinhole with Brown-Conrady radial and
// tangential distortion (royale's lens parameters). Camera frame: x right,
// y down, z forward.
#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "hal/depth_frame.hpp"

namespace sim_hal {

struct CameraIntrinsics {
  std::uint32_t width = 224;
  std::uint32_t height = 171;
  hal::LensParameters lens;
};

// The Pico Flexx: 224 x 171 over 62 x 45 degrees, with the principal point a
// little off centre and mild barrel distortion, as a real unit has.
CameraIntrinsics pico_flexx_intrinsics();

// Distorts a normalised image point (x/z, y/z).
Eigen::Vector2d distort(const hal::LensParameters& lens, const Eigen::Vector2d& undistorted);

// Inverse of distort(), by fixed-point iteration (converges for the mild
// distortion of this lens in a handful of steps).
Eigen::Vector2d undistort(const hal::LensParameters& lens, const Eigen::Vector2d& distorted);

// Whether a normalized image point (x / z, y / z) lies where the radial
// distortion still grows with the angle off axis; the lens model means
// nothing past that (this lens: about 53 deg off axis; its image's corners
// are at 39 deg).
bool within_lens_model(const hal::LensParameters& lens, const Eigen::Vector2d& undistorted);

// Projects a camera-frame point to pixel coordinates; false when behind the
// camera or outside the lens model (within_lens_model()), which a point far
// outside the image would otherwise alias into it.
bool project(const CameraIntrinsics& cam, const Eigen::Vector3d& p_cam, Eigen::Vector2d* pixel);

// Unit ray directions, camera frame, one per pixel (row major), computed once.
std::vector<Eigen::Vector3f> pixel_rays(const CameraIntrinsics& cam);

}  // namespace sim_hal
