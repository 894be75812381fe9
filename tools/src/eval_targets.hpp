#pragma once
// The detector's figures from hreval's tallies, against the project's targets:
// the proposed method over the rack-wall and Columbus scenarios (the
// rack-wall controls apart), per surface and pooled, so that a closing note
// quotes one table instead of summing the per-scenario rows by hand.
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "eval_metrics.hpp"

namespace tools {

// One column of the table: a surface kind, or the pool of several.
struct TargetColumn {
  std::string name;  // "rack wall", "Columbus", "pooled"
  Tally all_frames;  // every frame of its scenarios (merged scenario tallies)
  Tally no_target;   // those of its frames without a target
};

// The figures the issue names, from one column.
struct TargetFigures {
  int reach_found = 0, reach_frames = 0;          // frames in reach: target found / all
  int no_target_false = 0, no_target_frames = 0;  // frames without a target: false / all
  int state_right = 0, state_checked = 0;         // over correct detections
  double perpendicular_median_mm = 0.0, perpendicular_p95_mm = 0.0;  // NaN without detections
  double axis_median_deg = 0.0;
  double time_median_ms = 0.0;  // every frame, wall clock in hreval's process
};

TargetFigures target_figures(const TargetColumn& column);

// Frames grouped as hreval's "By surface and handrail length" table does:
// (surface, target length or "no target") to the proposed method's tally.
using SurfaceLengthTallies = std::map<std::pair<std::string, std::string>, Tally>;

// The columns from each scenario's surface and proposed-method tally: the
// rack walls and Columbus where any ran (the controls, "rack wall
// (control)", apart), then their pool; empty if neither ran.
std::vector<TargetColumn> target_columns(
    const std::vector<std::pair<std::string, const Tally*>>& scenarios,
    const SurfaceLengthTallies& by_surface_length);

// The report's section: a heading, what is counted, the table, and the
// flat walls' frames without a handrail with a false detection.
std::string targets_section(const std::vector<TargetColumn>& columns,
                            const SurfaceLengthTallies& by_surface_length);

// The Markdown table (a row per figure, a column per TargetColumn, then
// the target and whether the last column meets it).
std::string targets_markdown(const std::vector<TargetColumn>& columns);

// The same as one JSON object: {"columns": {NAME: {figures}}, "targets":
// {...}, "met": {...}} (met: judged on the last column).
std::string targets_json(const std::vector<TargetColumn>& columns);

}  // namespace tools
