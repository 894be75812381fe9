// hreval: renders the simulator's scenarios, runs the proposed and basic
// detectors on every frame and reports their accuracy against ground truth
// (Markdown table, Figure-15-style charts, a summary against the targets).
#include <dirent.h>
#include <sys/stat.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "common/cli_number.hpp"
#include "common/frame_convert.hpp"
#include "common/progress.hpp"
#include "estimator/config_io.hpp"
#include "estimator/handrail_detector.hpp"
#include "eval_chart.hpp"
#include "eval_metrics.hpp"
#include "eval_modules.hpp"
#include "eval_report_tables.hpp"
#include "eval_targets.hpp"
#include "output_dir.hpp"
#include "run_provenance.hpp"
#include "sim_camera_path.hpp"
#include "sim_hal/scenario.hpp"
#include "worst_frame.hpp"

// The flight configuration's use case (fsw_app/config/fsw_app.json).
constexpr const char* kUseCase = "MODE_9_5FPS_2000";

#ifndef HRP_SOURCE_DIR
#define HRP_SOURCE_DIR "."
#endif
#ifndef HRP_SCENARIO_DIR
#define HRP_SCENARIO_DIR "sim_hal/scenarios"
#endif

namespace {

using tools::kMethodNames;
using tools::pct;
using tools::raw_beside_depth;
using tools::ScenarioResult;
using tools::table2_rows;

void usage(FILE* out) {
  std::fprintf(out,
               "usage: hreval [options] [SCENARIO ...]\n"
               "Renders scenarios with the simulated Pico Flexx, runs the proposed and the\n"
               "basic detector on every frame, and reports accuracy against ground truth.\n"
               "A SCENARIO is a scenario file, or the name of one in the scenario folder\n"
               "(table2-iss for DIR/table2-iss.json). With none, runs every scenario there.\n\n"
               "options:\n"
               "  --scenarios DIR   scenario folder (default %s)\n"
               "  --out DIR         where report.md and the charts go (default hreval-out)\n"
               "  --max-frames N    at most N frames per scenario (for a quick look)\n"
               "  --no-pictures     no picture of each scenario's worst frame (for a report\n"
               "                    kept in the repository; the table still names the frame)\n"
               "  --true-length     configure the detector for each scenario's first handrail's\n"
               "                    bar length alone (default: every ISS length)\n"
               "  --camera depth|raw|both\n"
               "                    the frames' path: the depth renderer (default), raw phase\n"
               "                    frames through the robot's ToF processing, or both, the\n"
               "                    report's tables on the depth path and a table of every\n"
               "                    scenario's raw-path rates beside them\n"
               "  --seed-offset N   add N to every scenario's seed: the same scenes and poses\n"
               "                    with other sensor noise (how much a rate moves by chance)\n"
               "  --config FILE     detector configuration (JSON, as hrdetect --config): an\n"
               "                    option to try against the defaults; each scenario still\n"
               "                    sets the handrail geometry and the gripper angle\n"
               "  --candidate FILE  another detector configuration (JSON) to choose among, with\n"
               "                    the default (or --config) as the first: the report's\n"
               "                    leave-one-module-out section holds each module out in turn,\n"
               "                    chooses the candidate that scores best on the others and\n"
               "                    gives its figures on the held-out module (repeatable)\n"
               "  -h, --help        this text\n",
               HRP_SCENARIO_DIR);
}

// The modules in the report's order (any other after them).
const std::vector<std::string>& module_order() {
  static const std::vector<std::string> order = {"flat wall", "rack wall", "rack wall (control)",
                                                 "Columbus",  "Node 1",    "Node 2",
                                                 "Node 3",    "Cupola",    "module mesh"};
  return order;
}

// The target's bar length as a row label (frames without a target apart).
std::string length_label(const sim_hal::FrameTruth& truth, int target) {
  if (target < 0) return "no target";
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.2f m",
                truth.handrails[static_cast<std::size_t>(target)].length_m);
  return buf;
}

bool is_table2(const std::string& name) {
  return name.find("table2") != std::string::npos;
}
bool is_new(const ScenarioResult& r) {
  return r.surface != "flat wall";
}

// A scenario named without its folder and suffix (table2-iss) is the
// scenario folder's file of that name; a path that exists stays as given.
std::string resolve_scenario(const std::string& arg, const std::string& dir) {
  struct stat st {};
  if (stat(arg.c_str(), &st) == 0 || arg.find('/') != std::string::npos) return arg;
  const bool has_suffix = arg.size() > 5 && arg.compare(arg.size() - 5, 5, ".json") == 0;
  const std::string named = dir + "/" + arg + (has_suffix ? "" : ".json");
  return stat(named.c_str(), &st) == 0 ? named : arg;
}

std::vector<std::string> list_scenarios(const std::string& dir) {
  std::vector<std::string> files;
  if (DIR* d = opendir(dir.c_str())) {
    while (dirent* e = readdir(d)) {
      const std::string n = e->d_name;
      if (n.size() > 5 && n.compare(n.size() - 5, 5, ".json") == 0) files.push_back(dir + "/" + n);
    }
    closedir(d);
  }
  std::sort(files.begin(), files.end());
  return files;
}

}  // namespace

int main(int argc, char** argv) {
  std::string scenario_dir = HRP_SCENARIO_DIR, out_dir = "hreval-out", config_path;
  long max_frames = -1;
  bool true_length = false, pictures = true;
  long long seed_offset = 0;
  std::vector<std::string> paths = {"depth"};
  std::vector<std::string> files, candidate_paths;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto next = [&](const char* what) -> std::string {
      if (i + 1 >= argc) {
        std::fprintf(stderr, "hreval: %s needs a value (see --help)\n", what);
        std::exit(2);
      }
      return argv[++i];
    };
    if (a == "-h" || a == "--help") {
      usage(stdout);
      return 0;
    } else if (a == "--scenarios") {
      scenario_dir = next("--scenarios");
    } else if (a == "--out") {
      out_dir = next("--out");
    } else if (a == "--max-frames") {
      long long n = 0;
      std::string why;
      if (!tools::parse_whole_number(next("--max-frames"), 1, 1000000, &n, &why)) {
        std::fprintf(stderr, "hreval: --max-frames %s\n", why.c_str());
        return 2;
      }
      max_frames = static_cast<long>(n);
    } else if (a == "--true-length") {
      true_length = true;
    } else if (a == "--no-pictures") {
      pictures = false;
    } else if (a == "--seed-offset") {
      const std::string v = next("--seed-offset");
      char* end = nullptr;
      seed_offset = std::strtoll(v.c_str(), &end, 10);
      if (v.empty() || *end != '\0' || seed_offset < 0) {
        std::fprintf(stderr, "hreval: --seed-offset is a whole number >= 0, not '%s'\n", v.c_str());
        return 2;
      }
    } else if (a == "--config") {
      config_path = next("--config");
    } else if (a == "--candidate") {
      candidate_paths.push_back(next("--candidate"));
    } else if (a == "--camera") {
      const std::string v = next("--camera");
      if (v != "depth" && v != "raw" && v != "both") {
        std::fprintf(stderr, "hreval: --camera is depth, raw or both, not '%s'\n", v.c_str());
        return 2;
      }
      paths = v == "both" ? std::vector<std::string>{"depth", "raw"} : std::vector<std::string>{v};
    } else if (!a.empty() && a[0] == '-') {
      std::fprintf(stderr, "hreval: unknown option '%s' (see --help)\n", a.c_str());
      return 2;
    } else {
      files.push_back(a);
    }
  }
  for (std::string& f : files) f = resolve_scenario(f, scenario_dir);
  estimator::DetectorConfig base_cfg;
  if (!config_path.empty()) {
    std::string config_error;
    if (!estimator::load_detector_config(config_path, &base_cfg, &config_error)) {
      std::fprintf(stderr, "hreval: --config: %s\n", config_error.c_str());
      return 2;
    }
  }
  // The configurations the leave-one-module-out run chooses among: the
  // base first, then each --candidate, named by file.
  std::vector<estimator::DetectorConfig> candidates = {base_cfg};
  std::vector<std::string> candidate_names = {config_path.empty() ? "default" : config_path};
  for (const std::string& path : candidate_paths) {
    estimator::DetectorConfig c;
    std::string config_error;
    if (!estimator::load_detector_config(path, &c, &config_error)) {
      std::fprintf(stderr, "hreval: --candidate: %s\n", config_error.c_str());
      return 2;
    }
    candidates.push_back(c);
    candidate_names.push_back(path);
  }
  std::vector<tools::ModuleColumns> by_candidate_module(candidates.size());
  if (files.empty()) files = list_scenarios(scenario_dir);
  if (files.empty()) {
    std::fprintf(stderr, "hreval: no scenario files in %s (give --scenarios DIR or files)\n",
                 scenario_dir.c_str());
    return 2;
  }
  std::string dir_error;
  if (!tools::make_output_dir(out_dir, &dir_error)) {
    std::fprintf(stderr, "hreval: --out: %s\n", dir_error.c_str());
    return 2;
  }

  const sim_hal::CameraIntrinsics cam = sim_hal::pico_flexx_intrinsics();
  std::vector<ScenarioResult> results;
  // Per surface kind and the target's length, over every frame of every
  // scenario, each method.
  std::map<std::pair<std::string, std::string>, tools::Tally> by_surface_length[2];
  int failures = 0;
  std::vector<estimator::CloudPoint> buffer;
  std::vector<ScenarioResult> raw_results;  // --camera both: the raw path's
  for (const std::string& file : files) {
    sim_hal::Scenario sc;
    std::string error;
    if (!sim_hal::load_scenario(file, &sc, &error)) {
      std::fprintf(stderr, "hreval: %s (skipped)\n", error.c_str());
      ++failures;
      continue;
    }
    sc.seed += static_cast<std::uint64_t>(seed_offset);
    ScenarioResult r;
    r.name = sc.name;
    const bool round = !sc.scene.handrails.empty() &&
                       sc.scene.handrails[0].kind == sim_hal::HandrailKind::kPaperRound;
    r.kind = round ? "round" : "iss";
    r.surface = tools::module_of(sc.scene);
    // The rack-wall controls (one depth, to check the simulator scores a
    // flat rack like a flat wall) stay out of the rack walls' figures.
    if (r.surface == "rack wall" && r.name.find("control") != std::string::npos)
      r.surface = "rack wall (control)";
    // The flight default unless asked: the detector knows every ISS length
    // (and reports a 0.55 m bar's pose and target as before).
    const float length_m = true_length && !sc.scene.handrails.empty()
                               ? static_cast<float>(sc.scene.handrails[0].bar_length_m)
                               : 0.55f;
    // Each configuration as the scenario sets it: its handrail and gripper.
    auto for_scenario = [&](estimator::DetectorConfig c) {
      c.handrail =
          round ? estimator::paper_round_handrail(length_m) : estimator::iss_handrail(length_m);
      // Told the length, the detector looks for that one, not every ISS type.
      if (true_length) c.handrail_type_count = 0;
      c.gripper_angle_rad = static_cast<float>(sc.gripper_angle_deg * M_PI / 180.0);
      return c;
    };
    const estimator::DetectorConfig cfg = for_scenario(base_cfg);
    // The other candidates' proposed detectors (the first is `proposed`).
    // (Held by pointer: a detector points at its own clock and must not move.)
    std::vector<std::unique_ptr<estimator::HandrailDetector>> other_candidates;
    for (std::size_t c = 1; c < candidates.size(); ++c) {
      other_candidates.push_back(
          std::make_unique<estimator::HandrailDetector>(for_scenario(candidates[c])));
    }
    std::size_t n = sc.T_world_cam.size();
    if (max_frames >= 0) n = std::min(n, static_cast<std::size_t>(max_frames));
    const ScenarioResult blank = r;
    // The depth path first (the report's tables), then the raw path.
    for (const std::string& path : paths) {
      ScenarioResult& out = path == paths.front() ? r : raw_results.emplace_back(blank);
      estimator::HandrailDetector proposed(cfg), basic(cfg);
      tools::SimCameraPath camera(sc);
      if (!camera.open(path, out_dir + "/tof-calibration.json", kUseCase, &error)) {
        std::fprintf(stderr, "hreval: %s: %s\n", sc.name.c_str(), error.c_str());
        return 1;
      }
      tools::Progress progress("hreval " + sc.name + (paths.size() > 1 ? " " + path : ""), n);
      hal::DepthFrame frame;
      tools::WorstFrame worst;
      for (std::size_t f = 0; f < n && camera.next(&frame); ++f) {
        const sim_hal::FrameTruth truth =
            sim_hal::compute_truth(sc.scene, cam, sc.T_world_cam[f], f);
        const int target = tools::target_handrail(truth, cfg.gripper_angle_rad);
        const int reach_target = tools::target_handrail_in_reach(truth, cfg.gripper_angle_rad);
        const estimator::OrganizedCloud cloud = tools::to_estimator_cloud(frame, &buffer);
        const estimator::HandrailDetection d[2] = {
            proposed.detect(cloud, estimator::Method::kProposed),
            basic.detect(cloud, estimator::Method::kBasic)};
        // Each method's detection scored against the handrail it found,
        // where that is one the gripper could take as well as the target.
        int targets[2], reach_targets[2];
        for (int m = 0; m < 2; ++m) {
          targets[m] = tools::scored_target(d[m], truth, cfg.gripper_angle_rad, target, false);
          reach_targets[m] =
              tools::scored_target(d[m], truth, cfg.gripper_angle_rad, reach_target, true);
        }
        // Grouped by the frame's target, whatever either method found.
        const std::pair<std::string, std::string> group(out.surface, length_label(truth, target));
        const tools::Tally& scored = out.method[0].all;
        const std::size_t false_before = scored.false_frames.size();
        const std::size_t missed_before = scored.missed_frames.size();
        for (int m = 0; m < 2; ++m) {
          out.method[m].by_label[sc.pose_labels[f]].add(d[m], truth, targets[m], reach_targets[m]);
          out.method[m].all.add(d[m], truth, targets[m], reach_targets[m]);
          if (&out == &r) {
            by_surface_length[m][group].add(d[m], truth, targets[m], reach_targets[m]);
          }
        }
        if (&out == &r) {
          tools::add_to_module(by_candidate_module[0], out.surface, d[0], truth, targets[0],
                               reach_targets[0]);
          for (std::size_t c = 1; c < candidates.size(); ++c) {
            const estimator::HandrailDetection dc =
                other_candidates[c - 1]->detect(cloud, estimator::Method::kProposed);
            tools::add_to_module(
                by_candidate_module[c], out.surface, dc, truth,
                tools::scored_target(dc, truth, cfg.gripper_angle_rad, target, false),
                tools::scored_target(dc, truth, cfg.gripper_angle_rad, reach_target, true));
          }
        }
        const bool is_false = scored.false_frames.size() > false_before;
        if (&out == &r && (is_false || scored.missed_frames.size() > missed_before)) {
          worst.consider(frame, truth, d[0], is_false, targets[0], reach_targets[0]);
        }
        progress.update(f + 1);
      }
      if (const pico_flexx::RawDepthPipeline* p = camera.pipeline()) {
        out.tof = p->counts();
        out.tof_median_us = p->processing_median_us();
      }
      if (worst.any()) {
        out.worst_frame = static_cast<std::int64_t>(worst.frame_index());
        out.worst_reason = worst.reason();
        const std::string picture = "worst/" + sc.name + ".png";
        const std::string lines = "worst/" + sc.name + ".lines.json";
        // Without pictures the table still names the frame.
        if (pictures) {
          if (tools::make_output_dir(out_dir + "/worst", &error) &&
              worst.write_picture(out_dir + "/" + picture, out_dir + "/" + lines, sc.name, cfg,
                                  &error)) {
            out.worst_picture = picture;
            out.worst_lines = lines;
          } else {
            std::fprintf(stderr, "hreval: %s: the worst frame's picture: %s\n", sc.name.c_str(),
                         error.c_str());
          }
        }
      }
      const tools::Tally& p = out.method[0].all;
      progress.finish("detected " + pct(p.correct, p.target_frames) + ", false " +
                      pct(p.false_found, p.frames));
    }
    results.push_back(std::move(r));
  }

  // The report.
  std::ostringstream md;
  md << "# hreval report\n\nRun " << tools::run_provenance(HRP_SOURCE_DIR)
     << ".\n\nDetection: frames where the detector found the target handrail "
        "(within 5 cm of its centre line and 15° of its direction) over frames with a target "
        "(at least 30 % of a handrail in view). False: frames with a detection that is not the "
        "target, "
        "over all frames. State: BE / OE / NE right, over correct detections.\n\n"
     << "In reach: frames where a handrail is at least 35 % visible with "
        "the middle of its visible part 0.25 to 1.5 m away, and the detection rate over them.\n\n"
     << "| scenario | handrail | method | frames | with target | detected | false | state right | "
        "median ms | in reach | detected in reach |\n"
     << "|---|---|---|---|---|---|---|---|---|---|---|\n";
  for (const ScenarioResult& r : results) {
    for (int m = 0; m < 2; ++m) {
      const tools::Tally& t = r.method[m].all;
      char ms[16];
      std::snprintf(ms, sizeof ms, "%.2f", t.time_ms.median());
      md << "| " << r.name << " | " << r.kind << " | " << kMethodNames[m] << " | " << t.frames
         << " | " << t.target_frames << " | " << pct(t.correct, t.target_frames) << " | "
         << pct(t.false_found, t.frames) << " | "
         << (m == 0 ? pct(t.state_right, t.state_checked) : std::string("n/a")) << " | " << ms
         << " | " << t.reach_target_frames << " | " << pct(t.reach_correct, t.reach_target_frames)
         << " |\n";
    }
  }
  for (const ScenarioResult& r : results) {
    if (r.name.rfind("table2", 0) != 0) continue;
    table2_rows(md, r);
    std::string error;
    const std::string chart = out_dir + "/figure15-" + r.name + ".png";
    std::vector<tools::ChartSeries> series = {{"BASIC", &r.method[1].all},
                                              {"PROPOSED", &r.method[0].all}};
    if (tools::write_error_chart(chart, "POSE ERROR, " + r.name + " (ALL 8 CONFIGURATIONS)", series,
                                 &error)) {
      md << "\n![" << r.name << "](figure15-" << r.name << ".png)\n";
    } else {
      std::fprintf(stderr, "hreval: %s\n", error.c_str());
    }
  }
  // By surface and handrail length, the rack walls' Figure 15,
  // the state confusion on the approaches, and why frames failed.
  md << "\n## By module and handrail length\n\n"
     << "Every frame of every scenario run, grouped by the module the handrails stand in and the "
        "target's bar length (frames without a target apart: any detection there is false).\n\n"
     << "| surface | target length | method | frames | with target | detected | in reach | "
        "detected in reach | false |\n"
     << "|---|---|---|---|---|---|---|---|---|\n";
  for (const std::string& surface : module_order()) {
    for (const auto& kv : by_surface_length[0]) {
      if (kv.first.first != surface) continue;
      for (int m = 0; m < 2; ++m) {
        const tools::Tally& t = by_surface_length[m][kv.first];
        md << "| " << surface << " | " << kv.first.second << " | " << kMethodNames[m] << " | "
           << t.frames << " | " << t.target_frames << " | " << pct(t.correct, t.target_frames)
           << " | " << t.reach_target_frames << " | " << pct(t.reach_correct, t.reach_target_frames)
           << " | " << pct(t.false_found, t.frames) << " |\n";
      }
    }
  }
  // The frame time is over the frames of a kind of surface, not a
  // scenario: every frame of the surface's scenarios pooled, proposed method.
  md << "\nFrame time, proposed method, every frame of a surface's scenarios pooled "
        "(wall clock in this process; estimator_bench measures it alone):\n\n"
     << "| surface | frames | median ms | 90th percentile ms |\n|---|---|---|---|\n";
  for (const std::string& surface : module_order()) {
    std::vector<double> ms;
    for (const ScenarioResult& r : results) {
      if (r.surface != surface) continue;
      const std::vector<double>& v = r.method[0].all.time_ms.values;
      ms.insert(ms.end(), v.begin(), v.end());
    }
    if (ms.empty()) continue;
    std::sort(ms.begin(), ms.end());
    char line[160];
    std::snprintf(line, sizeof line, "| %s | %zu | %.2f | %.2f |\n", surface.c_str(), ms.size(),
                  ms[ms.size() / 2], ms[ms.size() * 9 / 10]);
    md << line;
  }
  // The figures against their targets, per surface and pooled.
  {
    std::vector<std::pair<std::string, const tools::Tally*>> scenarios;
    for (const ScenarioResult& r : results) scenarios.emplace_back(r.surface, &r.method[0].all);
    const std::vector<tools::TargetColumn> columns =
        tools::target_columns(scenarios, by_surface_length[0]);
    if (!columns.empty()) {
      md << tools::targets_section(columns, by_surface_length[0]);
      std::ofstream(out_dir + "/targets.json") << tools::targets_json(columns);
    }
  }
  // Each module held out in turn from the choice among the candidates.
  {
    const std::vector<tools::HeldOutChoice> choices =
        tools::leave_one_module_out(by_candidate_module);
    if (!choices.empty()) {
      md << tools::leave_one_module_out_section(choices, candidate_names);
      std::ofstream(out_dir + "/lomo.json")
          << tools::leave_one_module_out_json(choices, candidate_names);
    }
  }
  // The rack walls' Table 2, all lengths together, as Figure 15.
  {
    tools::Tally rack[2];
    int merged = 0;
    for (const ScenarioResult& r : results) {
      if (r.surface != "rack wall" || !is_table2(r.name)) continue;
      for (int m = 0; m < 2; ++m) rack[m].merge(r.method[m].all);
      ++merged;
    }
    if (merged > 0) {
      std::string error;
      const std::vector<tools::ChartSeries> series = {{"BASIC", &rack[1]}, {"PROPOSED", &rack[0]}};
      if (tools::write_error_chart(
              out_dir + "/figure15-rack-walls.png",
              "POSE ERROR, TABLE 2 ON RACK WALLS (" + std::to_string(merged) + " SCENARIOS)",
              series, &error)) {
        md << "\n## Table 2 on rack walls\n\n"
           << merged << " scenarios, every handrail length: proposed detected "
           << pct(rack[0].correct, rack[0].target_frames) << ", basic "
           << pct(rack[1].correct, rack[1].target_frames)
           << ".\n\n![Table 2 on rack walls](figure15-rack-walls.png)\n";
      } else {
        std::fprintf(stderr, "hreval: %s\n", error.c_str());
      }
      for (const ScenarioResult& r : results) {
        if (r.surface == "rack wall" && is_table2(r.name)) table2_rows(md, r);
      }
    }
  }
  // The proposed method's state against the truth's on the approaches.
  for (const ScenarioResult& r : results) {
    if (r.name.find("approach") == std::string::npos || !is_new(r)) continue;
    const tools::Tally& t = r.method[0].all;
    md << "\n### " << r.name << ": state confusion (proposed)\n\n"
       << "Rows: the target's state in the truth (NH: no target); columns: the state reported with "
          "a correct detection, a false detection, or nothing found.\n\n"
       << "| truth \\ said | BE | OE | NE | false | NH |\n|---|---|---|---|---|---|\n";
    const char* rows[] = {"BE", "OE", "NE", "NH"};
    for (int row = 0; row < tools::kConfusionRows; ++row) {
      md << "| " << rows[row];
      for (int c = 0; c < tools::kConfusionColumns; ++c) md << " | " << t.confusion[row][c];
      md << " |\n";
    }
  }
  if (!raw_results.empty()) raw_beside_depth(md, results, raw_results);
  md << "\n## Failures and the detector's reasons\n\n"
     << "Per scenario and method: the frames with a target where the target was not found, the "
        "frames with a false detection, and what the detector reported over all frames (FOUND: "
        "the target or a handrail in view; FALSE: a detection that is not; NO_LINE with its "
        "best line's first rejection). Worst frame, proposed method: the false detection with "
        "the most line inliers, else the missed target in reach most in view (then the nearest), "
        "else the missed target most in view; its picture shows every stage of the search that "
        "gave the result, with the true centre lines in green.\n\n"
     << "| scenario | method | missed frames | false frames | reasons | worst frame |\n"
     << "|---|---|---|---|---|---|\n";
  for (const ScenarioResult& r : results) {
    for (int m = 0; m < 2; ++m) {
      const tools::Tally& t = r.method[m].all;
      std::string reasons;
      for (const auto& kv : t.reasons) {
        if (!reasons.empty()) reasons += ", ";
        reasons += kv.first + " " + std::to_string(kv.second);
      }
      std::string worst = "-";
      if (m == 0 && r.worst_frame >= 0) {
        worst = std::to_string(r.worst_frame) + ": " + r.worst_reason;
        if (!r.worst_picture.empty()) {
          worst = "[" + worst + "](" + r.worst_picture + "), [lines](" + r.worst_lines + ")";
        }
      }
      md << "| " << r.name << " | " << kMethodNames[m] << " | "
         << tools::frame_ranges(t.missed_frames) << " | " << tools::frame_ranges(t.false_frames)
         << " | " << reasons << " | " << worst << " |\n";
    }
  }
  const std::string report = md.str();
  std::ofstream(out_dir + "/report.md") << report;
  std::printf("%s\n", report.c_str());

  // The summary against the numbers the project aims for.
  std::printf("## Summary against targets\n\n");
  for (const ScenarioResult& r : results) {
    const tools::Tally& p = r.method[0].all;
    if (r.name.rfind("table2", 0) == 0) {
      std::printf(
          "- %s: detection %.1f %% (target >= 99), position error perpendicular to the bar %.1f mm "
          "mean "
          "(target <= 5), axis %.2f deg, normal %.2f deg mean (target <= 1)\n",
          r.name.c_str(), p.rate(p.correct, p.target_frames), p.perpendicular.mean(), p.axis.mean(),
          p.normal.mean());
    } else if (r.name == "clutter-only") {
      std::printf("- %s: false detections %.1f %% of frames (target <= 1)\n", r.name.c_str(),
                  p.rate(p.false_found, p.frames));
    } else if (is_new(r) && p.target_frames == 0) {
      std::printf("- %s (%s, no handrail): false detections %.1f %% of frames (target <= 1)\n",
                  r.name.c_str(), r.surface.c_str(), p.rate(p.false_found, p.frames));
    } else if (is_new(r)) {
      std::printf("- %s (%s): detection %.1f %% (in reach %.1f %%), false %.1f %% of frames\n",
                  r.name.c_str(), r.surface.c_str(), p.rate(p.correct, p.target_frames),
                  p.rate(p.reach_correct, p.reach_target_frames), p.rate(p.false_found, p.frames));
    }
  }
  std::printf("\nreport: %s/report.md\n", out_dir.c_str());
  return failures ? 1 : 0;
}
