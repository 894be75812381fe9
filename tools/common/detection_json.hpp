#pragma once
#include <string>

#include "estimator/types.hpp"

namespace tools {

// One line of hrdetect's output (see tools/README.md for the fields).
std::string detection_to_json(const std::string& frame, const estimator::HandrailDetection& d);

}  // namespace tools
