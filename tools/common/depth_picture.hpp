#pragma once
// Pictures of depth frames: false colour by range, invalid pixels black,
// with handrails' centre lines drawn over them.
#include <Eigen/Core>
#include <functional>

#include "hal/depth_frame.hpp"
#include "png_image.hpp"

namespace tools {

constexpr int kPictureScale = 3;

Image depth_picture(const hal::DepthFrame& frame);

// Draws the segment a-b (camera frame) using `project` (false = not in
// front of the camera), clipped to the picture.
void draw_segment(Image* img,
                  const std::function<bool(const Eigen::Vector3d&, Eigen::Vector2d*)>& project,
                  const Eigen::Vector3d& a, const Eigen::Vector3d& b, Rgb colour,
                  int thickness = 2);

}  // namespace tools
