#pragma once
#include <string>

#include "estimator/handrail_tracker.hpp"
#include "estimator/line_trace.hpp"
#include "estimator/mount_surfaces.hpp"
#include "estimator/types.hpp"

namespace tools {

// One line of hrdetect's output (see tools/README.md for the fields).
std::string detection_to_json(const std::string& frame, const estimator::HandrailDetection& d);

// The surfaces in view and the mounts the detector searched on the last
// frame (hrdetect --mounts): {"plane": {"normal": [...], "d_m": d},
// "surfaces_m": [...], "offsets_m": [...], "front_pixels": [...],
// "plane_front_pixels": n}, distances from the dominant plane along its
// normal (toward the camera), metres.
std::string mounts_to_json(const estimator::Plane& dominant, const estimator::MountHypotheses& m);

// Every line the detector tested on the last frame (hrdetect --lines): an
// array of {"search": n, "search_mount_m": m, "verdict": "...", "inliers":
// n} objects, in the order tested, with "middle", "axis" (camera frame)
// and "visible_length_m" once the line had a centre line, "front_m" and
// "mount_m" (the front's height above the mount it was seated on, that
// mount from the dominant plane; before seating, "front_above_search_m"),
// and "ends_seen" once its ends were walked.
std::string line_trace_to_json(const estimator::LineTrace& trace);

// The line with the most inliers among every line the frame's searches
// tested (the first of equals): the bar when it was in view, whichever
// search refused it. Null when no line was traced. Lines the trace had to
// drop are not among them.
const estimator::LineTraceEntry* best_supported_line(const estimator::LineTrace& trace);

// That line as hrdetect's "best_line" (null for none): {"search": n,
// "mount_m": m, "verdict": "...", "inliers": n, "middle_cam": [x,y,z],
// "axis_cam": [x,y,z], "visible_length_m": l, "front_height_m": h}, camera
// frame, metres. front_height_m is the front's height above mount_m: the
// mount the line was seated on, or, before seating, the one searched
// (both from the dominant plane). The last four are null for a line that
// never had a centre line.
std::string best_line_to_json(const estimator::LineTraceEntry* best);

// `object` (one JSON object, as detection_to_json writes it) with the line
// trace added as its "lines" array, and "lines_not_kept" when the trace
// had to drop any.
std::string with_line_trace(std::string object, const estimator::LineTrace& trace);

// The tracker's state: {"event": ..., "position": [...], "axis": [...],
// "normal": [...], "target_position": [...]} in the world frame, or
// {"event": ...} without a track.
std::string track_to_json(const estimator::TrackedHandrail& t);

}  // namespace tools
