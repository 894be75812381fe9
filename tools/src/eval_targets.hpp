#pragma once
// The detector's figures from hreval's tallies, against the project's targets:
// the proposed method over the module scenarios (the procedural rack walls
// one of them, their controls apart), per module and pooled, so that a note
// quotes one table instead of summing the per-scenario rows by hand.
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "eval_metrics.hpp"

namespace tools {

// One column of the table: a surface kind, or the pool of several.
struct TargetColumn {
  std::string name;  // "rack wall", "Columbus", "Node 1", ..., "pooled"
  Tally all_frames;  // every frame of its scenarios (merged scenario tallies)
  Tally no_target;   // those of its frames without a target
};

// The figures with targets, from one column.
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

// The columns from each scenario's module and proposed-method tally: every
// module that ran but the flat walls and the rack-wall controls, then
// their pool; empty if none ran.
std::vector<TargetColumn> target_columns(
    const std::vector<std::pair<std::string, const Tally*>>& scenarios,
    const SurfaceLengthTallies& by_surface_length);

// The report's section: a heading, what is counted, the table, and the
// flat walls' frames without a handrail with a false detection.
std::string targets_section(const std::vector<TargetColumn>& columns,
                            const SurfaceLengthTallies& by_surface_length);

// The Markdown table (a row per figure, a column per TargetColumn, then
// the target and whether the last column meets it).
// With judge_last_only false, the last column says whether every column
// meets the target and names those that do not.
std::string targets_markdown(const std::vector<TargetColumn>& columns, bool judge_last_only = true);

// One column's figures as a JSON object.
std::string target_figures_json(const TargetFigures& f);

// Whether a module's figures are held to the targets: every module but the
// rack-wall controls (one depth; they check the simulator).
bool is_judged_module(const std::string& module);

// The same as one JSON object: {"columns": {NAME: {figures}}, "targets":
// {...}, "met": {...}} (met: judged on the last column).
std::string targets_json(const std::vector<TargetColumn>& columns);

}  // namespace tools
