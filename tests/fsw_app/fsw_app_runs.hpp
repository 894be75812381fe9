#pragma once
// Running fsw_app on recorded frames and reading back what it did: the
// helpers the frame-replay and recording tests share (a run's output,
// exit status and summary; the estimates in an LCM log; a recorded run and
// its replay into an estimator alone).
#include <sys/types.h>
#include <unistd.h>

#include <lcm/lcm-cpp.hpp>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <string>
#include <vector>

#include "child_process.hpp"
#include "cmocka_cpp.hpp"
#include "hrp/handrail_estimate_t.hpp"
#include "summary_json.hpp"
#include "test_data.hpp"

namespace fsw_app_runs {

// The fsw_app program under test (the test's argv[1]).
inline std::string g_program;

inline std::string source(const std::string& rel) {
  const char* d = std::getenv("HRP_SOURCE_DIR");
  return std::string(d ? d : ".") + "/" + rel;
}

inline std::string work_path(const std::string& name) {
  return "/tmp/hrp_replay_" + std::to_string(getpid()) + "_" + name;
}

// --- The program.

struct Run {
  int exit_status = -1;
  std::string output;  // stdout and stderr
  testing_support::Summary summary;
  double number(const char* key) const { return summary.number(key); }
};

// Waits for it; its output, exit status and (when named) JSON summary.
inline Run finish_program(pid_t pid, const std::string& out_path, const std::string& summary = "") {
  Run r;
  r.exit_status = testing_support::wait_for_exit(pid);
  r.output = testing_support::read_text(out_path);
  std::remove(out_path.c_str());
  if (!summary.empty()) {
    std::string error;
    if (!testing_support::read_summary(summary, &r.summary, &error)) {
      print_error("no summary (%s): %s\n%s\n", summary.c_str(), error.c_str(), r.output.c_str());
      fail();
    }
    std::remove(summary.c_str());
  }
  return r;
}

inline Run run_program(const std::string& program, std::vector<std::string> args,
                       const std::string& summary = "") {
  const std::string out_path = work_path("out.txt");
  if (!summary.empty()) std::remove(summary.c_str());
  return finish_program(testing_support::spawn_program(program, std::move(args), out_path),
                        out_path, summary);
}

// fsw_app's arguments: the shipped configuration, quiet, and the summary.
// The budget is 10 s: the recorded and replayed estimates are compared
// exactly, and on a loaded machine (a sanitizer build) a stall could make
// a frame miss the 200 ms budget in one run and not in the other.
inline std::vector<std::string> fsw_app_args(const std::vector<std::string>& args,
                                             const std::string& summary) {
  std::vector<std::string> all = {"--config", source("fsw_app/config/fsw_app.json"), "--quiet",
                                  "--budget-us", "10000000"};
  all.insert(all.end(), args.begin(), args.end());
  if (!summary.empty()) {
    all.push_back("--summary-json");
    all.push_back(summary);
  }
  return all;
}

inline Run run_fsw_app(const std::vector<std::string>& args, const std::string& summary = "") {
  return run_program(g_program, fsw_app_args(args, summary), summary);
}

struct Estimate {
  int state = -1;
  double p[3] = {0, 0, 0};
  double q[4] = {0, 0, 0, 0};
};

// HANDRAIL_ESTIMATE by frame id (the first for each frame), and the count
// of DEPTH_FRAME events.
inline std::map<std::int64_t, Estimate> read_estimates(const std::string& path, int* depth_frames) {
  std::map<std::int64_t, Estimate> out;
  lcm::LogFile log(path, "r");
  assert_true(log.good());
  *depth_frames = 0;
  while (const lcm::LogEvent* e = log.readNextEvent()) {
    if (e->channel == "DEPTH_FRAME") ++*depth_frames;
    if (e->channel != "HANDRAIL_ESTIMATE") continue;
    hrp::handrail_estimate_t m{};  // zeroed: GCC 12 at -O2 cannot see decode() fills it
    assert_true(m.decode(e->data, 0, e->datalen) > 0);
    if (out.count(m.frame_id)) continue;
    Estimate est;
    est.state = m.state;
    for (int k = 0; k < 3; ++k) est.p[k] = m.T_cam_handrail.position_m[k];
    for (int k = 0; k < 4; ++k) est.q[k] = m.T_cam_handrail.quat_wxyz[k];
    out[m.frame_id] = est;
  }
  return out;
}

// Every frame estimated in both runs agrees exactly (same frames, same
// detector); returns how many were compared.
inline int compare_estimates(const std::map<std::int64_t, Estimate>& a,
                             const std::map<std::int64_t, Estimate>& b) {
  int compared = 0;
  for (const auto& [id, ea] : a) {
    const auto it = b.find(id);
    if (it == b.end()) continue;
    const Estimate& eb = it->second;
    if (ea.state != eb.state) {
      print_error("frame %lld: state %d recorded, %d replayed\n", static_cast<long long>(id),
                  ea.state, eb.state);
      fail();
    }
    for (int k = 0; k < 3; ++k) assert_true(std::fabs(ea.p[k] - eb.p[k]) < 1e-9);
    for (int k = 0; k < 4; ++k) assert_true(std::fabs(ea.q[k] - eb.q[k]) < 1e-9);
    ++compared;
  }
  return compared;
}

// Records a run on the recorded PCD frames (5 fps) with --publish-frames.
inline std::string record_run() {
  const std::string rec = work_path("rec.lcm");
  const Run r = run_fsw_app(
      {"--hal", "real", "--camera-replay", source("tests/data"), "--tasks", "camera,estimator",
       "--publish-frames", "--duration", "2.5", "--lcm-url", "memq://", "--log", rec},
      work_path("rec.json"));
  assert_int_equal(r.exit_status, 0);
  assert_true(r.number("frames_processed") >= 8);
  return rec;
}

// Every good frame played reached the estimator, and each was estimated or,
// when a stall bunched frames together and the estimator was behind,
// dropped as designed (the oldest first). Most must have been estimated.
inline void assert_frames_accounted_for(const Run& r, int good_frames) {
  const auto received = static_cast<int>(r.number("frames_received"));
  const auto processed = static_cast<int>(r.number("frames_processed"));
  const auto dropped = static_cast<int>(r.number("frames_dropped"));
  std::printf("%d good frames played: %d received, %d processed, %d dropped\n", good_frames,
              received, processed, dropped);
  assert_int_equal(received, good_frames);
  assert_int_equal(processed + dropped, received);
  assert_true(processed * 3 >= good_frames * 2);
}

struct Replay {
  Run run;
  std::map<std::int64_t, Estimate> estimates;
};

// Replays `log` into an estimator running alone (memq) and reads back what
// it estimated.
inline Replay replay_into_estimator(const std::string& log, const std::string& name) {
  const std::string replay_log = work_path(name + ".lcm");
  Replay out;
  out.run = run_fsw_app({"--frames-from-log", log, "--lcm-url", "memq://", "--log", replay_log},
                        work_path(name + ".json"));
  std::printf("%s", out.run.output.c_str());
  assert_int_equal(out.run.exit_status, 0);
  int depth_frames = 0;
  out.estimates = read_estimates(replay_log, &depth_frames);
  std::remove(replay_log.c_str());
  return out;
}

// Each frame processed in the replay published one estimate; those of
// frames estimated in both runs agree exactly, and they are most frames
// (either run may have dropped a few when a stall left it behind).
inline void assert_estimates_agree(const std::map<std::int64_t, Estimate>& recorded,
                                   const Replay& replay, int good_frames) {
  const int compared = compare_estimates(recorded, replay.estimates);
  std::printf("%d good frames; %d estimates compared, all equal\n", good_frames, compared);
  assert_int_equal(static_cast<long>(replay.estimates.size()),
                   static_cast<long>(replay.run.number("frames_processed")));
  assert_true(compared * 2 >= good_frames);
}

}  // namespace fsw_app_runs
