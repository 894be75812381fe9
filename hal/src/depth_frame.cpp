#include "hal/depth_frame.hpp"

#include <cmath>

namespace hal {

bool is_valid(const DepthPoint& p) {
  return p.confidence != 0 && std::isfinite(p.x_m) && std::isfinite(p.y_m) &&
         std::isfinite(p.z_m) && p.z_m > 0.0f;
}

std::size_t count_valid(const DepthFrame& frame) {
  std::size_t n = 0;
  const std::size_t total = static_cast<std::size_t>(frame.width) * frame.height;
  for (std::size_t i = 0; i < total; ++i) n += is_valid(frame.points[i]) ? 1 : 0;
  return n;
}

}  // namespace hal
