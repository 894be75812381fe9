#pragma once
// hreval's figures per module, and the leave-one-module-out choice: a
// detector option counts as evidence only on a module it was not chosen
// with. Each candidate configuration is scored on every module; for each
// module in turn, the candidate that scores best on the other modules is
// chosen and its figures on the held-out module are the ones reported.
#include <map>
#include <string>
#include <vector>

#include "eval_targets.hpp"
#include "sim_hal/scene.hpp"

namespace tools {

// The module a scenario's handrails stand in: the ISS module mesh it
// renders ("Columbus", "Node 1", "Node 2", "Node 3", "Cupola", "module mesh"
// for another), else "rack wall" (the simulator's procedural racks, one
// more module) or "flat wall".
std::string module_of(const sim_hal::Scene& scene);

// The tallies of one candidate configuration, per module.
using ModuleColumns = std::map<std::string, TargetColumn>;

// Adds a frame's detection to its module's column.
void add_to_module(ModuleColumns& columns, const std::string& module,
                   const estimator::HandrailDetection& d, const sim_hal::FrameTruth& truth,
                   int target, int reach_target);

// How a candidate ranks on a set of modules: the mean of their in-reach
// detection rates (percent) less ten times the mean of their false
// detection rates on frames without a handrail (percent), so one false
// detection in twelve empty frames outweighs 80 points of detection.
// Modules without such frames add nothing to that part.
double choice_score(const ModuleColumns& columns, const std::vector<std::string>& modules);

struct HeldOutChoice {
  std::string module;         // held out
  std::size_t candidate = 0;  // chosen on the other modules
  double development_score = 0.0;
  TargetColumn held_out;  // the chosen candidate's figures on the held-out module
};

// For each scored module with frames: the candidate (index into
// `per_candidate`; ties go to the lower index) with the best choice_score on
// the other scored modules, and its column on the held-out one.
std::vector<HeldOutChoice> leave_one_module_out(const std::vector<ModuleColumns>& per_candidate);

// The report's section: per held-out module, the chosen candidate's name,
// its score on the others, and the figures against the targets.
std::string leave_one_module_out_section(const std::vector<HeldOutChoice>& choices,
                                         const std::vector<std::string>& candidate_names);

// The same as JSON: {"candidates": [...], "held_out": {MODULE: {"chosen":
// NAME, "development_score": S, figures...}}}.
std::string leave_one_module_out_json(const std::vector<HeldOutChoice>& choices,
                                      const std::vector<std::string>& candidate_names);

}  // namespace tools
