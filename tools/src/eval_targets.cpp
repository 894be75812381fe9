#include "eval_targets.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <sstream>

namespace tools {
namespace {

double percent(int n, int of) {
  return of ? 100.0 * n / of : NAN;
}

// A number for JSON: null where there is none.
std::string json_number(double v, int decimals) {
  if (!std::isfinite(v)) return "null";
  char buf[48];
  std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
  return buf;
}

std::string fixed(double v, int decimals, const char* unit) {
  if (!std::isfinite(v)) return "-";
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f%s", decimals, v, unit);
  return buf;
}

std::string count_of(int n, int of, bool with_percent) {
  if (of == 0) return "-";
  char buf[96];
  if (with_percent) {
    std::snprintf(buf, sizeof buf, "%d of %d (%.2f %%)", n, of, percent(n, of));
  } else {
    std::snprintf(buf, sizeof buf, "%d of %d", n, of);
  }
  return buf;
}

// One figure with a target: how to show it, its target, and the test.
struct Figure {
  const char* key;    // JSON name
  int json_decimals;  // 0 for a count
  const char* label;  // the table's row
  const char* target_text;
  double target;  // the bound, in the figure's own unit
  bool at_least;  // the figure must be >= target (else <=)
  std::function<double(const TargetFigures&)> value;
  std::function<std::string(const TargetFigures&)> cell;
};

const std::vector<Figure>& figures() {
  static const std::vector<Figure> list = {
      {"in_reach_found_pct", 4, "frames in reach: the handrail found", ">= 98 %", 98.0, true,
       [](const TargetFigures& f) { return percent(f.reach_found, f.reach_frames); },
       [](const TargetFigures& f) { return count_of(f.reach_found, f.reach_frames, true); }},
      {"no_target_false_frames", 0, "frames without a handrail: a false detection", "0", 0.0, false,
       [](const TargetFigures& f) {
         return f.no_target_frames ? static_cast<double>(f.no_target_false) : NAN;
       },
       [](const TargetFigures& f) {
         return count_of(f.no_target_false, f.no_target_frames, false);
       }},
      {"state_right_pct", 4, "state (BE / OE / NE) right, over correct detections", ">= 90 %", 90.0,
       true, [](const TargetFigures& f) { return percent(f.state_right, f.state_checked); },
       [](const TargetFigures& f) { return count_of(f.state_right, f.state_checked, true); }},
      {"perpendicular_median_mm", 4, "position error perpendicular to the bar, median", "<= 3 mm",
       3.0, false, [](const TargetFigures& f) { return f.perpendicular_median_mm; },
       [](const TargetFigures& f) { return fixed(f.perpendicular_median_mm, 2, " mm"); }},
      {"perpendicular_p95_mm", 4, "position error perpendicular to the bar, 95th percentile",
       "<= 10 mm", 10.0, false, [](const TargetFigures& f) { return f.perpendicular_p95_mm; },
       [](const TargetFigures& f) { return fixed(f.perpendicular_p95_mm, 2, " mm"); }},
      {"axis_median_deg", 4, "axis error, median", "<= 0.5 deg", 0.5, false,
       [](const TargetFigures& f) { return f.axis_median_deg; },
       [](const TargetFigures& f) { return fixed(f.axis_median_deg, 3, " deg"); }},
      {"frame_time_median_ms", 4,
       "frame time, median (hreval's wall clock; estimator_bench is the "
       "measure of record)",
       "<= 0.5 ms", 0.5, false, [](const TargetFigures& f) { return f.time_median_ms; },
       [](const TargetFigures& f) { return fixed(f.time_median_ms, 2, " ms"); }},
  };
  return list;
}

// Met, not met, or nothing to judge (no frames of that kind).
const char* verdict(const Figure& fig, const TargetFigures& f) {
  const double v = fig.value(f);
  if (!std::isfinite(v)) return "-";
  return (fig.at_least ? v >= fig.target : v <= fig.target) ? "yes" : "no";
}

}  // namespace

bool is_judged_module(const std::string& module) {
  return module != "rack wall (control)";
}

TargetFigures target_figures(const TargetColumn& c) {
  TargetFigures f;
  f.reach_found = c.all_frames.reach_correct;
  f.reach_frames = c.all_frames.reach_target_frames;
  f.no_target_false = c.no_target.false_found;
  f.no_target_frames = c.no_target.frames;
  f.state_right = c.all_frames.state_right;
  f.state_checked = c.all_frames.state_checked;
  f.perpendicular_median_mm = c.all_frames.correct_perpendicular.median();
  f.perpendicular_p95_mm = c.all_frames.correct_perpendicular.percentile(95.0);
  f.axis_median_deg = c.all_frames.correct_axis.median();
  f.time_median_ms = c.all_frames.time_ms.median();
  return f;
}

std::vector<TargetColumn> target_columns(
    const std::vector<std::pair<std::string, const Tally*>>& scenarios,
    const SurfaceLengthTallies& by_surface_length) {
  std::vector<TargetColumn> columns;
  TargetColumn pooled{"pooled", {}, {}};
  // Every module but the flat walls (their own section) and the rack-wall
  // controls, in a fixed order.
  std::vector<std::string> modules;
  for (const auto& s : scenarios) {
    if (s.first == "flat wall" || !is_judged_module(s.first)) continue;
    bool seen = false;
    for (const std::string& m : modules) seen |= m == s.first;
    if (!seen) modules.push_back(s.first);
  }
  std::sort(modules.begin(), modules.end());
  for (const std::string& surface : modules) {
    TargetColumn c{surface, {}, {}};
    for (const auto& s : scenarios) {
      if (s.first == surface) c.all_frames.merge(*s.second);
    }
    if (c.all_frames.frames == 0) continue;
    const auto none = by_surface_length.find({surface, "no target"});
    if (none != by_surface_length.end()) c.no_target = none->second;
    pooled.all_frames.merge(c.all_frames);
    pooled.no_target.merge(c.no_target);
    columns.push_back(std::move(c));
  }
  if (!columns.empty()) columns.push_back(std::move(pooled));
  return columns;
}

std::string targets_section(const std::vector<TargetColumn>& columns,
                            const SurfaceLengthTallies& by_surface_length) {
  std::ostringstream md;
  md << "\n## Figures against the targets\n\nProposed method, the report's frame path, over the "
        "module scenarios run (the procedural rack walls are one module; their controls "
        "apart), per module and pooled; met or not judged on the pooled column. Frames without a "
        "handrail: those of "
        "the surface's frames with no target (any detection there is false). Errors: over the "
        "correct detections of the target (the Table 2 tables and charts count every detection "
        "of a frame with a target, as the paper's Figure 15 does). Also in `targets.json`.\n\n"
     << targets_markdown(columns);
  const auto flat = by_surface_length.find({"flat wall", "no target"});
  if (flat != by_surface_length.end()) {
    md << "\nFlat walls (to stay no worse than the default detector): " << flat->second.false_found
       << " of " << flat->second.frames << " frames without a handrail with a false detection.\n";
  }
  return md.str();
}

std::string targets_markdown(const std::vector<TargetColumn>& columns, bool judge_last_only) {
  std::vector<TargetFigures> f;
  for (const TargetColumn& c : columns) f.push_back(target_figures(c));
  std::ostringstream md;
  md << "| figure |";
  for (const TargetColumn& c : columns) md << ' ' << c.name << " |";
  md << " target | "
     << (judge_last_only ? (columns.empty() ? std::string("-") : columns.back().name) + " meets it"
                         : std::string("every column meets it"))
     << " |\n|---|";
  for (std::size_t k = 0; k < columns.size(); ++k) md << "---|";
  md << "---|---|\n";
  for (const Figure& fig : figures()) {
    md << "| " << fig.label << " |";
    for (const TargetFigures& one : f) md << ' ' << fig.cell(one) << " |";
    md << ' ' << fig.target_text << " | ";
    if (f.empty()) {
      md << '-';
    } else if (judge_last_only) {
      md << verdict(fig, f.back());
    } else {
      // "yes", or "no:" and the columns that miss it.
      std::string missed;
      for (std::size_t k = 0; k < f.size(); ++k) {
        if (verdict(fig, f[k])[0] == 'n') missed += (missed.empty() ? "" : ", ") + columns[k].name;
      }
      md << (missed.empty() ? "yes" : "no: " + missed);
    }
    md << " |\n";
  }
  return md.str();
}

std::string target_figures_json(const TargetFigures& f) {
  std::ostringstream js;
  js << "{\"in_reach_found\": " << f.reach_found << ", \"in_reach_frames\": " << f.reach_frames
     << ", \"no_target_frames\": " << f.no_target_frames << ", \"state_right\": " << f.state_right
     << ", \"state_checked\": " << f.state_checked;
  for (const Figure& fig : figures()) {
    js << ", \"" << fig.key << "\": " << json_number(fig.value(f), fig.json_decimals);
  }
  js << '}';
  return js.str();
}

std::string targets_json(const std::vector<TargetColumn>& columns) {
  std::ostringstream js;
  js << "{\"columns\": {";
  for (std::size_t k = 0; k < columns.size(); ++k) {
    js << (k ? ", " : "") << '"' << columns[k].name
       << "\": " << target_figures_json(target_figures(columns[k]));
  }
  js << "}, \"targets\": {";
  bool first = true;
  for (const Figure& fig : figures()) {
    js << (first ? "" : ", ") << '"' << fig.key << "\": \"" << fig.target_text << '"';
    first = false;
  }
  js << "}, \"met\": {";
  first = true;
  // The pooled column (the last) is the one held to the targets.
  const TargetFigures pooled = columns.empty() ? TargetFigures{} : target_figures(columns.back());
  for (const Figure& fig : figures()) {
    const char* v = columns.empty() ? "-" : verdict(fig, pooled);
    js << (first ? "" : ", ") << '"' << fig.key << "\": "
       << (v[0] == 'y'   ? "true"
           : v[0] == 'n' ? "false"
                         : "null");
    first = false;
  }
  js << "}}\n";
  return js.str();
}

}  // namespace tools
