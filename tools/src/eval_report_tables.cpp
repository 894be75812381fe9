#include "eval_report_tables.hpp"

#include <algorithm>
#include <cstdio>

namespace tools {

double valid_share(const pico_flexx::PipelineCounts& c) {
  std::uint64_t all = 0;
  for (std::uint64_t n : c.pixels_by_state) all += n;
  return all ? static_cast<double>(c.pixels_by_state[0]) / static_cast<double>(all) : 0.0;
}

const char* const kMethodNames[2] = {"proposed", "basic"};

std::string pct(int n, int of) {
  if (of == 0) return "-";
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.1f %%", 100.0 * n / of);
  return buf;
}

void table2_rows(std::ostringstream& md, const ScenarioResult& r) {
  md << "\n### " << r.name << " (" << r.kind << " handrail): errors in the true handrail frame\n\n"
     << "x = along the wall normal, y = across the bar, z = along the bar (both ends seen only); "
        "mean ± standard deviation over detections, millimetres and degrees.\n\n"
     << "| config | method | detected | x mm | y mm | z mm | ⊥ bar mm | roll ° | pitch ° | yaw ° | "
        "axis ° | normal ° | beam mm | median ms |\n"
     << "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  auto row = [&](const std::string& label, const char* method, const tools::Tally& t) {
    char ms[16];
    std::snprintf(ms, sizeof ms, "%.2f", t.time_ms.median());
    md << "| " << label << " | " << method << " | " << pct(t.correct, t.target_frames) << " | "
       << t.x.mean_sd() << " | " << t.y.mean_sd() << " | " << t.z.mean_sd() << " | "
       << t.perpendicular.mean_sd() << " | " << t.roll.mean_sd(2) << " | " << t.pitch.mean_sd(2)
       << " | " << t.yaw.mean_sd(2) << " | " << t.axis.mean_sd(2) << " | " << t.normal.mean_sd(2)
       << " | " << t.beam.mean_sd() << " | " << ms << " |\n";
  };
  for (const auto& kv : r.method[0].by_label) {
    for (int m = 0; m < 2; ++m) {
      auto it = r.method[m].by_label.find(kv.first);
      if (it != r.method[m].by_label.end()) row(kv.first, kMethodNames[m], it->second);
    }
  }
  for (int m = 0; m < 2; ++m) row("**all**", kMethodNames[m], r.method[m].all);
}

void raw_beside_depth(std::ostringstream& md, const std::vector<ScenarioResult>& depth,
                      const std::vector<ScenarioResult>& raw) {
  md << "\n## Raw path beside depth path (proposed method)\n\n"
     << "Depth: the depth renderer's frames. Raw: the raw renderer's phase frames (MODE_9) "
        "through the robot's ToF processing, on the calibration file the simulated unit wrote. "
        "Difference in points of detection rate (target: within 1 point of the depth path). "
        "Mostly invalid: frames with under half their pixels valid.\n\n"
     << "| scenario | with target | detected depth | detected raw | difference | false depth | "
        "false raw | in reach depth | in reach raw | raw valid pixels | mostly invalid | ToF "
        "median ms |\n"
     << "|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  // The raw path's target is two-sided (within 1 point either way); the
  // count of scenarios not more than 1 point below is kept beside it.
  int within = 0, not_below = 0, scored = 0;
  double worst_below = 0.0, worst_above = 0.0;
  for (std::size_t i = 0; i < depth.size() && i < raw.size(); ++i) {
    const tools::Tally& d = depth[i].method[0].all;
    const tools::Tally& r = raw[i].method[0].all;
    std::string diff = "-";
    if (d.target_frames > 0) {
      const double points = r.rate(r.correct, r.target_frames) - d.rate(d.correct, d.target_frames);
      char buf[32];
      std::snprintf(buf, sizeof buf, "%+.1f", points);
      diff = buf;
      ++scored;
      if (points >= -1.0) ++not_below;
      if (points >= -1.0 && points <= 1.0) ++within;
      worst_below = std::min(worst_below, points);
      worst_above = std::max(worst_above, points);
    }
    char share[32], ms[32];
    std::snprintf(share, sizeof share, "%.1f %%", 100.0 * valid_share(raw[i].tof));
    std::snprintf(ms, sizeof ms, "%.2f", 1e-3 * static_cast<double>(raw[i].tof_median_us));
    md << "| " << depth[i].name << " | " << d.target_frames << " | "
       << pct(d.correct, d.target_frames) << " | " << pct(r.correct, r.target_frames) << " | "
       << diff << " | " << pct(d.false_found, d.frames) << " | " << pct(r.false_found, r.frames)
       << " | " << pct(d.reach_correct, d.reach_target_frames) << " | "
       << pct(r.reach_correct, r.reach_target_frames) << " | " << share << " | "
       << raw[i].tof.frames_mostly_invalid << " of " << raw[i].tof.frames_in << " | " << ms
       << " |\n";
  }
  char line[256];
  std::snprintf(line, sizeof line,
                "\n%d of %d scenarios with a target within 1 point of the depth path either way "
                "(%d no more than 1 point below it; furthest below %+.1f, above %+.1f points).\n",
                within, scored, not_below, worst_below, worst_above);
  md << line;
}

}  // namespace tools
