#pragma once
// hreval's per-scenario results and the report tables built from them:
// the Table 2 rows of one scenario and the raw path beside the depth path.
#include <cstdint>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "eval_metrics.hpp"
#include "pico_flexx/raw_depth_pipeline.hpp"

namespace tools {

struct MethodTallies {
  std::map<std::string, tools::Tally> by_label;  // e.g. "table2-3"
  tools::Tally all;
};

struct ScenarioResult {
  std::string name, kind;
  std::string surface;      // "flat wall", "rack wall", "Columbus"
  MethodTallies method[2];  // proposed, basic
  // The raw path's processing (frames == 0 on the depth path).
  pico_flexx::PipelineCounts tof;
  std::int64_t tof_median_us = -1;
  // The proposed method's worst failed frame on the report's path, why it
  // failed, its picture and its line trace (relative to the output folder;
  // empty if none).
  std::int64_t worst_frame = -1;
  std::string worst_reason, worst_picture, worst_lines;
};

extern const char* const kMethodNames[2];  // proposed, basic

// A share of `of` as "12.3 %", or "-" when there is nothing to share.
std::string pct(int n, int of);
// The share of the raw path's pixels that came out valid.
double valid_share(const pico_flexx::PipelineCounts& c);
// One scenario's errors in the true handrail frame, by pose label.
void table2_rows(std::ostringstream& md, const ScenarioResult& r);
// Every scenario's proposed-method rates on the raw path beside the depth
// path's, and what the ToF processing made of the raw frames.
void raw_beside_depth(std::ostringstream& md, const std::vector<ScenarioResult>& depth,
                      const std::vector<ScenarioResult>& raw);

}  // namespace tools
