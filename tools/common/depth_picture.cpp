#include "depth_picture.hpp"

#include <algorithm>
#include <cmath>

namespace tools {

Image depth_picture(const hal::DepthFrame& frame) {
  float lo = 1e9f, hi = 0.0f;
  const std::size_t n = static_cast<std::size_t>(frame.width) * frame.height;
  for (std::size_t i = 0; i < n; ++i) {
    if (!hal::is_valid(frame.points[i])) continue;
    lo = std::min(lo, frame.points[i].z_m);
    hi = std::max(hi, frame.points[i].z_m);
  }
  Image img(static_cast<int>(frame.width), static_cast<int>(frame.height));
  for (std::uint32_t r = 0; r < frame.height; ++r) {
    for (std::uint32_t c = 0; c < frame.width; ++c) {
      const hal::DepthPoint& p = frame.at(r, c);
      if (hal::is_valid(p)) {
        img.set(static_cast<int>(c), static_cast<int>(r),
                false_colour(hi > lo ? (p.z_m - lo) / (hi - lo) : 0.0));
      }
    }
  }
  return img.scaled(kPictureScale);
}

void draw_segment(Image* img,
                  const std::function<bool(const Eigen::Vector3d&, Eigen::Vector2d*)>& project,
                  const Eigen::Vector3d& a, const Eigen::Vector3d& b, Rgb colour, int thickness) {
  constexpr int kSteps = 60;
  Eigen::Vector2d prev;
  bool have_prev = false;
  for (int k = 0; k <= kSteps; ++k) {
    const Eigen::Vector3d p = a + (b - a) * (static_cast<double>(k) / kSteps);
    Eigen::Vector2d px;
    if (!project(p, &px)) {
      have_prev = false;
      continue;
    }
    px = (px + Eigen::Vector2d(0.5, 0.5)) * kPictureScale;
    if (have_prev) img->line(prev.x(), prev.y(), px.x(), px.y(), colour, thickness);
    prev = px;
    have_prev = true;
  }
}

}  // namespace tools
