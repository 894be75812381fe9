#pragma once
#include <string>

#include "estimator/handrail_tracker.hpp"
#include "estimator/types.hpp"

namespace tools {

// One line of hrdetect's output (see tools/README.md for the fields).
std::string detection_to_json(const std::string& frame, const estimator::HandrailDetection& d);

// The tracker's state: {"event": ..., "position": [...], "axis": [...],
// "normal": [...], "target_position": [...]} in the world frame, or
// {"event": ...} without a track.
std::string track_to_json(const estimator::TrackedHandrail& t);

}  // namespace tools
