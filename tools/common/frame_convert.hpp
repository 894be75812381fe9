#pragma once
// From the HAL's depth frame to the estimator's cloud. The two point types
// share a layout by design; copying keeps the estimator free of any
// dependency on the HAL and costs well under a millisecond.
#include <vector>

#include "estimator/organized_cloud.hpp"
#include "hal/depth_frame.hpp"

namespace tools {

// `buffer` is resized only when the frame is larger than any before.
estimator::OrganizedCloud to_estimator_cloud(const hal::DepthFrame& frame,
                                             std::vector<estimator::CloudPoint>* buffer);

}  // namespace tools
