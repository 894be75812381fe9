#include "frame_convert.hpp"

namespace tools {

estimator::OrganizedCloud to_estimator_cloud(const hal::DepthFrame& frame,
                                             std::vector<estimator::CloudPoint>* buffer) {
  const std::size_t n = static_cast<std::size_t>(frame.width) * frame.height;
  if (buffer->size() < n) buffer->resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const hal::DepthPoint& p = frame.points[i];
    (*buffer)[i] = {p.x_m, p.y_m, p.z_m, p.noise_m, p.gray_value, p.confidence};
  }
  estimator::OrganizedCloud cloud;
  cloud.frame_id = frame.frame_id;
  cloud.capture_time_us = frame.capture_time_us;
  cloud.width = frame.width;
  cloud.height = frame.height;
  cloud.points = buffer->data();
  return cloud;
}

}  // namespace tools
