// hrcompare: do two runs of the flight software agree on the handrail?
// Reads the HANDRAIL_ESTIMATE messages of two LCM logs (say, the host
// build and the armhf build under qemu-arm, both on the same recorded
// frames) and compares them frame by frame: state, and where a handrail
// was found its position and orientation in the camera frame.
#include <lcm/lcm-cpp.hpp>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <map>
#include <string>

#include "hrp/handrail_estimate_t.hpp"

namespace {

const char* const kChannel = "HANDRAIL_ESTIMATE";

void usage(FILE* out) {
  std::fprintf(out,
               "usage: hrcompare LOG_A LOG_B [options]\n"
               "Compares the handrail estimates (channel %s) of two LCM logs frame by\n"
               "frame: the state must be the same, and where a handrail was found its\n"
               "position and orientation in the camera frame must agree within the\n"
               "tolerances. Exit status 0 when every frame in both logs agrees and there\n"
               "are enough of them, 1 when not, 2 on a usage or file error.\n\n"
               "  --frames N      the logs replayed a folder of N frames in a loop: frame\n"
               "                  ids are taken modulo N and the first estimate of each\n"
               "                  recorded frame is compared (default: ids as they are)\n"
               "  --tol-mm X      position tolerance, millimetres (default 1)\n"
               "  --tol-deg X     orientation tolerance, degrees (default 0.2)\n"
               "  --min-frames M  at least M frames must be in both logs (default 10)\n"
               "  -h, --help      this text\n",
               kChannel);
}

struct Options {
  std::string log_a, log_b;
  long frames = 0;
  double tol_mm = 1.0, tol_deg = 0.2;
  long min_frames = 10;
};

bool parse_number(const char* text, double* out) {
  char* end = nullptr;
  *out = std::strtod(text, &end);
  return end != text && *end == '\0' && std::isfinite(*out);
}

// 0: run; 1: help shown; 2: bad usage (reported).
int parse_options(int argc, char** argv, Options* o) {
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "-h" || a == "--help") {
      usage(stdout);
      return 1;
    }
    if (a == "--frames" || a == "--tol-mm" || a == "--tol-deg" || a == "--min-frames") {
      double v = 0.0;
      if (i + 1 >= argc || !parse_number(argv[i + 1], &v) || v < 0.0) {
        std::fprintf(stderr, "hrcompare: %s needs a non-negative number\n", a.c_str());
        return 2;
      }
      ++i;
      if (a == "--frames") o->frames = static_cast<long>(v);
      if (a == "--tol-mm") o->tol_mm = v;
      if (a == "--tol-deg") o->tol_deg = v;
      if (a == "--min-frames") o->min_frames = static_cast<long>(v);
      continue;
    }
    if (!a.empty() && a[0] == '-') {
      std::fprintf(stderr, "hrcompare: unknown option %s (see --help)\n", a.c_str());
      return 2;
    }
    if (o->log_a.empty()) {
      o->log_a = a;
    } else if (o->log_b.empty()) {
      o->log_b = a;
    } else {
      std::fprintf(stderr, "hrcompare: one log too many: %s\n", a.c_str());
      return 2;
    }
  }
  if (o->log_b.empty()) {
    std::fprintf(stderr, "hrcompare: two LCM logs are needed (see --help)\n");
    return 2;
  }
  return 0;
}

// The first estimate of each (recorded) frame in a log. False when the
// file cannot be read as an LCM log; messages that do not decode are
// counted and skipped.
bool read_estimates(const std::string& path, long modulus,
                    std::map<long, hrp::handrail_estimate_t>* out, long* undecodable) {
  lcm::LogFile log(path, "r");
  if (!log.good()) {
    std::fprintf(stderr, "hrcompare: %s: cannot open as an LCM log\n", path.c_str());
    return false;
  }
  *undecodable = 0;
  for (const lcm::LogEvent* e = log.readNextEvent(); e != nullptr; e = log.readNextEvent()) {
    if (e->channel != kChannel) continue;
    hrp::handrail_estimate_t m;
    if (m.decode(e->data, 0, static_cast<int>(e->datalen)) < 0) {
      ++*undecodable;
      continue;
    }
    const long key =
        modulus > 0 ? static_cast<long>(m.frame_id % modulus) : static_cast<long>(m.frame_id);
    out->emplace(key, m);  // keeps the first
  }
  return true;
}

double position_error_mm(const hrp::pose_t& a, const hrp::pose_t& b) {
  double sq = 0.0;
  for (int k = 0; k < 3; ++k)
    sq += (a.position_m[k] - b.position_m[k]) * (a.position_m[k] - b.position_m[k]);
  return 1000.0 * std::sqrt(sq);
}

// The angle of the rotation between two unit quaternions.
double angle_error_deg(const hrp::pose_t& a, const hrp::pose_t& b) {
  double dot = 0.0;
  for (int k = 0; k < 4; ++k) dot += a.quat_wxyz[k] * b.quat_wxyz[k];
  dot = std::fmin(1.0, std::fabs(dot));
  return 2.0 * std::acos(dot) * 180.0 / M_PI;
}

const char* state_name(int state) {
  static const char* const kNames[] = {"NH", "BE", "OE", "NE"};
  return state >= 0 && state < 4 ? kNames[state] : "?";
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  const int parsed = parse_options(argc, argv, &o);
  if (parsed != 0) return parsed == 1 ? 0 : 2;

  std::map<long, hrp::handrail_estimate_t> a, b;
  long bad_a = 0, bad_b = 0;
  if (!read_estimates(o.log_a, o.frames, &a, &bad_a) ||
      !read_estimates(o.log_b, o.frames, &b, &bad_b)) {
    return 2;
  }
  if (bad_a + bad_b > 0) {
    std::printf("skipped undecodable estimates: %ld in %s, %ld in %s\n", bad_a, o.log_a.c_str(),
                bad_b, o.log_b.c_str());
  }
  std::printf("%6s  %5s %5s  %9s  %9s  %s\n", "frame", "A", "B", "pos mm", "angle deg", "verdict");
  long common = 0, agree = 0;
  double worst_mm = 0.0, worst_deg = 0.0;
  for (const auto& [key, ea] : a) {
    const auto it = b.find(key);
    if (it == b.end()) continue;
    const hrp::handrail_estimate_t& eb = it->second;
    ++common;
    bool same = ea.state == eb.state;
    double mm = 0.0, deg = 0.0;
    if (same && ea.state != hrp::handrail_estimate_t::STATE_NH) {
      mm = position_error_mm(ea.T_cam_handrail, eb.T_cam_handrail);
      deg = angle_error_deg(ea.T_cam_handrail, eb.T_cam_handrail);
      worst_mm = std::fmax(worst_mm, mm);
      worst_deg = std::fmax(worst_deg, deg);
      same = mm <= o.tol_mm && deg <= o.tol_deg;
    }
    agree += same ? 1 : 0;
    std::printf("%6ld  %5s %5s  %9.3f  %9.3f  %s\n", key, state_name(ea.state),
                state_name(eb.state), mm, deg, same ? "agree" : "DIFFER");
  }
  std::printf(
      "%ld frames in both logs (%zu in %s, %zu in %s); %ld agree; worst %.3f mm, %.3f deg "
      "(tolerance %.3g mm, %.3g deg)\n",
      common, a.size(), o.log_a.c_str(), b.size(), o.log_b.c_str(), agree, worst_mm, worst_deg,
      o.tol_mm, o.tol_deg);
  if (common < o.min_frames) {
    std::printf("FAIL: only %ld frames in both logs, %ld needed\n", common, o.min_frames);
    return 1;
  }
  if (agree != common) {
    std::printf("FAIL: %ld frames differ\n", common - agree);
    return 1;
  }
  std::printf("OK\n");
  return 0;
}
