#include "eval_modules.hpp"

#include <cmath>
#include <cstdio>
#include <sstream>

namespace tools {
namespace {

// The mesh files' names (sim_hal/assets/iss_modules/) and their modules.
struct KnownModule {
  const char* file_part;
  const char* name;
};
constexpr KnownModule kKnownModules[] = {
    {"columbus", "Columbus"}, {"node_1", "Node 1"}, {"node_2", "Node 2"},
    {"node_3", "Node 3"},     {"cupola", "Cupola"},
};

double percent(int n, int of) {
  return of ? 100.0 * n / of : NAN;
}

std::string score_text(double s) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.1f", s);
  return buf;
}

}  // namespace

std::string module_of(const sim_hal::Scene& scene) {
  for (const sim_hal::SceneMesh& m : scene.meshes) {
    const std::size_t slash = m.path.find_last_of('/');
    const std::string file = slash == std::string::npos ? m.path : m.path.substr(slash + 1);
    for (const KnownModule& k : kKnownModules) {
      if (file.find(k.file_part) != std::string::npos) return k.name;
    }
  }
  if (!scene.meshes.empty()) return "module mesh";
  return scene.rack_walls.empty() ? "flat wall" : "rack wall";
}

void add_to_module(ModuleColumns& columns, const std::string& module,
                   const estimator::HandrailDetection& d, const sim_hal::FrameTruth& truth,
                   int target, int reach_target) {
  TargetColumn& c = columns[module];
  c.name = module;
  c.all_frames.add(d, truth, target, reach_target);
  // A frame without a handrail to take: any detection there is false.
  if (target < 0) c.no_target.add(d, truth, target, reach_target);
}

double choice_score(const ModuleColumns& columns, const std::vector<std::string>& modules) {
  double found_sum = 0.0, false_sum = 0.0;
  int found_n = 0, false_n = 0;
  for (const std::string& m : modules) {
    const auto it = columns.find(m);
    if (it == columns.end()) continue;
    const Tally& all = it->second.all_frames;
    const Tally& none = it->second.no_target;
    if (all.reach_target_frames > 0) {
      found_sum += percent(all.reach_correct, all.reach_target_frames);
      ++found_n;
    }
    if (none.frames > 0) {
      false_sum += percent(none.false_found, none.frames);
      ++false_n;
    }
  }
  const double found = found_n ? found_sum / found_n : 0.0;
  const double falses = false_n ? false_sum / false_n : 0.0;
  return found - 10.0 * falses;
}

std::vector<HeldOutChoice> leave_one_module_out(const std::vector<ModuleColumns>& per_candidate) {
  std::vector<HeldOutChoice> out;
  if (per_candidate.empty()) return out;
  std::vector<std::string> modules;
  for (const auto& kv : per_candidate.front()) {
    if (is_judged_module(kv.first) && kv.second.all_frames.frames > 0) modules.push_back(kv.first);
  }
  for (const std::string& held : modules) {
    std::vector<std::string> others;
    for (const std::string& m : modules) {
      if (m != held) others.push_back(m);
    }
    HeldOutChoice choice;
    choice.module = held;
    choice.development_score = -INFINITY;
    for (std::size_t c = 0; c < per_candidate.size(); ++c) {
      const double s = choice_score(per_candidate[c], others);
      if (s > choice.development_score) {
        choice.development_score = s;
        choice.candidate = c;
      }
    }
    const auto it = per_candidate[choice.candidate].find(held);
    if (it != per_candidate[choice.candidate].end()) choice.held_out = it->second;
    choice.held_out.name = held;
    out.push_back(std::move(choice));
  }
  return out;
}

std::string leave_one_module_out_section(const std::vector<HeldOutChoice>& choices,
                                         const std::vector<std::string>& candidate_names) {
  std::ostringstream md;
  md << "\n## Leave one module out\n\n"
     << "Each module in turn is held out: among the " << candidate_names.size()
     << " candidate configuration(s) (";
  for (std::size_t k = 0; k < candidate_names.size(); ++k) {
    md << (k ? ", " : "") << '`' << candidate_names[k] << '`';
  }
  md << "), the one with the best score on the other modules is chosen (mean in-reach "
        "detection % less ten times the mean false % on frames without a handrail), and its "
        "figures on the held-out module are these. A module no choice was made with: the "
        "figures are evidence.\n\n"
     << "| held-out module | chosen | score on the others |\n|---|---|---|\n";
  std::vector<TargetColumn> columns;
  for (const HeldOutChoice& c : choices) {
    md << "| " << c.module << " | `" << candidate_names[c.candidate] << "` | "
       << score_text(c.development_score) << " |\n";
    columns.push_back(c.held_out);
  }
  if (!columns.empty()) md << '\n' << targets_markdown(columns, false);
  return md.str();
}

std::string leave_one_module_out_json(const std::vector<HeldOutChoice>& choices,
                                      const std::vector<std::string>& candidate_names) {
  std::ostringstream js;
  js << "{\"candidates\": [";
  for (std::size_t k = 0; k < candidate_names.size(); ++k) {
    js << (k ? ", " : "") << '"' << candidate_names[k] << '"';
  }
  js << "], \"held_out\": {";
  for (std::size_t k = 0; k < choices.size(); ++k) {
    const HeldOutChoice& c = choices[k];
    js << (k ? ", " : "") << '"' << c.module << "\": {\"chosen\": \""
       << candidate_names[c.candidate] << "\", \"development_score\": "
       << (std::isfinite(c.development_score) ? score_text(c.development_score) : "null")
       << ", \"figures\": " << target_figures_json(target_figures(c.held_out)) << '}';
  }
  js << "}}\n";
  return js.str();
}

}  // namespace tools
