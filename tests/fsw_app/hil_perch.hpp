#pragma once
// One hardware-in-loop perch of the fsw_app program, for the tests that
// fly it (test_hil_faults.cpp, test_hostile_bus.cpp): the run on its own
// udpm port (memq:// where the host has no multicast route), its summary
// read back, and the host-stall rule that repeats a run the host starved.
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <initializer_list>
#include <string>
#include <vector>

#include <lcm/lcm-cpp.hpp>

#include "child_process.hpp"
#include "cmocka_cpp.hpp"
#include "summary_json.hpp"

namespace hil_perch {

inline std::string g_program;
inline int g_port = 7700;
inline bool g_udpm = true;  // false where the host has no multicast route

inline std::string source(const std::string& rel) {
  const char* d = std::getenv("HRP_SOURCE_DIR");
  return std::string(d ? d : ".") + "/" + rel;
}

struct Outcome : testing_support::Summary {
  int exit_status = -1;
};

// Runs one perch with extra arguments; each run gets its own udpm port so
// that runs never hear each other.
inline Outcome run(const std::string& scenario, std::vector<std::string> extra) {
  const std::string summary =
      "/tmp/hrp_hil_" + std::to_string(getpid()) + "_" + std::to_string(g_port) + ".json";
  std::remove(summary.c_str());
  std::vector<std::string> args = {
      "--config",
      source("fsw_app/config/fsw_app.json"),
      "--hal",
      "sim",
      "--scenario",
      source("sim_hal/scenarios/" + scenario + ".json"),
      "--perch",
      "--quiet",
      "--timeout",
      "60",
      "--lcm-url",
      g_udpm ? "udpm://239.255.76.67:" + std::to_string(g_port++) + "?ttl=0" : "memq://",
      "--summary-json",
      summary};
  args.insert(args.end(), extra.begin(), extra.end());
  Outcome out;
  out.exit_status = testing_support::run_to_exit(g_program, args);
  std::string error;
  if (!testing_support::read_summary(summary, &out, &error)) {
    print_error("no summary from the run (%s): %s\n", summary.c_str(), error.c_str());
    fail();
  }
  std::remove(summary.c_str());
  std::printf(
      "  %s: %s %s %s (longest gaps: arm loop %.0f ms, frames %.0f ms; capture to estimate "
      "%.0f ms)\n",
      scenario.c_str(), out.text("arm_state").c_str(), out.text("fault").c_str(),
      out.text("fault_text").c_str(), out.number("arm_longest_gap_ms"),
      out.number("camera_longest_gap_ms"), out.number("estimator_longest_latency_ms"));
  return out;
}

// A run is real time on a host that may be shared: when its outcome is
// not the expected one and the program's own figures show a task stalled
// by the host, the host is to blame, not the code under test; the run is
// repeated (at most kStallRepeats times), and says so. This VM has bad
// spells: once in CI three runs in a row stalled (arm loop 753, 270 and
// 548 ms) while the cases before and after ran on time. A wrong outcome
// with every task on time fails at once. On time, the arm loop's gaps stay
// under 80 ms (period 50 ms), the frames come every 200 ms (5 fps; a burst
// of corrupt frames is still delivered, so still timed) and an estimate
// follows its capture within 65 ms (render, ring, detect; debug build).
constexpr double kArmStallMs = 150.0;
constexpr double kFrameStallMs = 500.0;
constexpr double kEstimateStallMs = 200.0;  // one frame period
constexpr int kStallRepeats = 4;

inline std::string host_stall(const Outcome& o) {
  char why[160];
  if (o.number("arm_longest_gap_ms") > kArmStallMs) {
    std::snprintf(why, sizeof why, "the arm loop stalled for %.0f ms",
                  o.number("arm_longest_gap_ms"));
  } else if (o.number("camera_longest_gap_ms") > kFrameStallMs) {
    std::snprintf(why, sizeof why, "no frame for %.0f ms", o.number("camera_longest_gap_ms"));
  } else if (o.number("estimator_longest_latency_ms") > kEstimateStallMs) {
    std::snprintf(why, sizeof why, "an estimate came %.0f ms after its capture",
                  o.number("estimator_longest_latency_ms"));
  } else {
    return "";
  }
  return why;
}

template <typename Expect>
Outcome run_expecting(const std::string& scenario, const std::vector<std::string>& extra,
                      Expect expected) {
  Outcome o = run(scenario, extra);
  for (int again = 0; again < kStallRepeats && !expected(o); ++again) {
    const std::string stall = host_stall(o);
    if (stall.empty()) break;
    std::printf("  NOTE: %s (host); running this case again\n", stall.c_str());
    o = run(scenario, extra);
  }
  return o;
}

inline bool perched_within_1cm(const Outcome& o) {
  return o.flag("perched") && o.flag("success");
}

// A number inside the summary's nested objects ("localization", "approach",
// "filter", "mean_m"); -1 when missing.
inline double nested(const Outcome& o, std::initializer_list<const char*> path) {
  return o.number_at(path);
}

inline double input_rejections(const Outcome& o, const char* channel, const char* reason) {
  const formats::JsonValue* inputs = o.json.find("inputs");
  const formats::JsonValue* c = inputs ? inputs->find(channel) : nullptr;
  const formats::JsonValue* r = c ? c->find("rejected") : nullptr;
  const formats::JsonValue* n = r ? r->find(reason) : nullptr;
  return n && n->is_number() ? n->number : -1.0;
}

template <typename Msg>
std::vector<std::uint8_t> encoded(const Msg& m) {
  std::vector<std::uint8_t> bytes(static_cast<std::size_t>(m.getEncodedSize()));
  m.encode(bytes.data(), 0, static_cast<int>(bytes.size()));
  return bytes;
}

// The program under test, and a udpm port of this process's own.
inline void init(const char* program) {
  g_program = program;
  g_port = 7700 + static_cast<int>(getpid() % 200);
  lcm::LCM probe("udpm://239.255.76.67:" + std::to_string(g_port) + "?ttl=0");
  if (!probe.good()) {
    g_udpm = false;
    std::printf(
        "NOTE: udpm unavailable here (no multicast route: ip link set lo multicast on; ip "
        "route add 224.0.0.0/4 dev lo); running in-process on memq:// instead\n");
  }
}

}  // namespace hil_perch
