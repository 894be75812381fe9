// hrlocalize: a recorded run's localizer inputs through the localization
// task again, offline. A run recorded with `fsw_app --log LOG` holds every
// IMU sample, general-purpose (GP) pose and handrail estimate the localizer
// took, and in a HIL run the world's true pose (TRUTH_POSE). hrlocalize
// publishes them in log order into fsw_app's LocalizationTask on a clock
// set from the log's timestamps, and reports what the filter made of each
// handrail estimate and how far its pose was from the truth. A filter change
// can then be judged on the exact inputs of a run that went wrong (a
// perch's 0.5 m divergence along the bar was found this way).
#include <lcm/lcm-cpp.hpp>

#include <array>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "estimator/localization/handrail_map.hpp"
#include "estimator/localization/status.hpp"
#include "fsw_app/app_config.hpp"
#include "fsw_app/lcm_hub.hpp"
#include "fsw_app/localization_task.hpp"
#include "fsw_app/msg_convert.hpp"
#include "hal/clock.hpp"
#include "hrp/handrail_estimate_t.hpp"
#include "hrp/robot_pose_t.hpp"
#include "sim_hal/scenario.hpp"

namespace {

namespace loc = estimator::localization;

void usage(FILE* out) {
  std::fprintf(out,
               "usage: hrlocalize LOG [options]\n"
               "Replays the localizer's inputs of an LCM log recorded with fsw_app --log\n"
               "(%s, %s, %s)\n"
               "through fsw_app's localization task, in log order. Prints a line per\n"
               "handrail estimate: its capture time (s from the first estimate's), state,\n"
               "the filter's verdict, features used and gated, NIS over its degrees of\n"
               "freedom, and the filter's position error against the log's %s\n"
               "(a HIL run's truth), world frame, mm; then a summary: the verdicts counted,\n"
               "and the error while the handrail held the pose and over the whole run.\n"
               "With --scenario (the run's scene) the error is also scored relative to the\n"
               "handrail, as perching needs it: the body in the filter's map against the\n"
               "body in the true handrail frame, out from the wall, across and along the\n"
               "bar; the world error carries the map's own error besides.\n\n"
               "options:\n"
               "  --config FILE   fsw_app configuration (default fsw_app/config/fsw_app.json)\n"
               "  --scenario FILE the run's scenario (sim_hal/scenarios/*.json): relative error\n"
               "  --quiet         the summary only\n"
               "  -h, --help      this text\n\n"
               "exit status: 0 when the log was replayed; 1 when it holds no localizer\n"
               "input, or a handrail estimate did not decode (named on stderr; the rest are\n"
               "replayed); 2 for bad options, a configuration that does not load, or a log\n"
               "that cannot be read.\n",
               fsw_app::channel::kImuSample, fsw_app::channel::kGpPose,
               fsw_app::channel::kHandrailEstimate, fsw_app::channel::kTruthPose);
}

struct Options {
  std::string log;
  std::string config = "fsw_app/config/fsw_app.json";
  std::string scenario;  // empty: the world error only
  bool quiet = false;
};

// 0: run; 1: help shown; 2: bad usage (reported).
int parse_options(int argc, char** argv, Options* o) {
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "-h" || a == "--help") {
      usage(stdout);
      return 1;
    } else if (a == "--quiet") {
      o->quiet = true;
    } else if (a == "--config" || a == "--scenario") {
      if (i + 1 >= argc) {
        std::fprintf(stderr, "hrlocalize: %s needs a file (see --help)\n", a.c_str());
        return 2;
      }
      (a == "--config" ? o->config : o->scenario) = argv[++i];
    } else if (!a.empty() && a[0] == '-') {
      std::fprintf(stderr, "hrlocalize: unknown option '%s' (see --help)\n", a.c_str());
      return 2;
    } else if (o->log.empty()) {
      o->log = a;
    } else {
      std::fprintf(stderr, "hrlocalize: one log only; '%s' is a second\n", a.c_str());
      return 2;
    }
  }
  if (o->log.empty()) {
    std::fprintf(stderr, "hrlocalize: a log is needed (see --help)\n");
    return 2;
  }
  return 0;
}

const char* state_name(int state) {
  static const char* const kNames[] = {"NH", "BE", "OE", "NE"};
  return state >= 0 && state < 4 ? kNames[state] : "?";
}

// Mean and largest of a non-negative quantity.
struct Stat {
  double sum = 0.0, max = 0.0;
  long n = 0;
  void add(double v) {
    sum += v;
    max = std::fmax(max, v);
    ++n;
  }
  double mean() const { return n > 0 ? sum / static_cast<double>(n) : 0.0; }
};

// The filter's handrail update counts, BE/OE then NE, by status.
std::array<std::uint32_t, 2 * loc::kNumUpdateStatus> handrail_counts(
    const fsw_app::LocalizationTask& task) {
  std::array<std::uint32_t, 2 * loc::kNumUpdateStatus> c{};
  const loc::FilterCounters& f = task.filter().counters();
  for (int s = 0; s < loc::kNumUpdateStatus; ++s) {
    const auto st = static_cast<loc::UpdateStatus>(s);
    c[static_cast<std::size_t>(s)] = f.count(loc::MeasurementKind::kHandrailEnds, st);
    c[static_cast<std::size_t>(loc::kNumUpdateStatus + s)] =
        f.count(loc::MeasurementKind::kHandrailNoEnd, st);
  }
  return c;
}

// The scene's handrails in the filter's map convention: x = wall normal,
// z = along the bar, origin on the centre line at the bar's middle.
std::vector<Eigen::Isometry3d> true_handrail_frames(const sim_hal::Scenario& sc) {
  std::vector<Eigen::Isometry3d> frames;
  for (const sim_hal::Handrail& h : sc.scene.handrails) {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    const Eigen::Vector3d axis = (h.end_point(1) - h.end_point(0)).normalized();
    T.linear().col(0) = h.normal.normalized();
    T.linear().col(1) = axis.cross(T.linear().col(0));
    T.linear().col(2) = axis;
    T.translation() = 0.5 * (h.end_point(0) + h.end_point(1));
    frames.push_back(T);
  }
  return frames;
}

// The body's error relative to the handrail the filter mapped (the scene's
// handrail nearest the map's origin, its axis sign matched to the map's),
// in that handrail's frame: x out from the wall, y across, z along the bar.
Eigen::Vector3d relative_error_m(const std::vector<Eigen::Isometry3d>& handrails,
                                 const loc::HandrailMap& map, const Eigen::Isometry3d& T_est,
                                 const Eigen::Isometry3d& T_true) {
  std::size_t best = 0;
  for (std::size_t k = 1; k < handrails.size(); ++k) {
    if ((handrails[k].translation() - map.T_world_handrail.translation()).norm() <
        (handrails[best].translation() - map.T_world_handrail.translation()).norm()) {
      best = k;
    }
  }
  Eigen::Isometry3d T_wh = handrails[best];
  if (map.T_world_handrail.linear().col(2).dot(T_wh.linear().col(2)) < 0.0) {
    T_wh.linear() = loc::flip_axis(T_wh.linear());
  }
  const Eigen::Vector3d p_rel = (T_wh * map.T_world_handrail.inverse() * T_est).translation();
  return T_wh.linear().transpose() * (p_rel - T_true.translation());
}

bool is_input(const std::string& channel) {
  return channel == fsw_app::channel::kImuSample || channel == fsw_app::channel::kGpPose ||
         channel == fsw_app::channel::kHandrailEstimate;
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  const int parsed = parse_options(argc, argv, &o);
  if (parsed == 1) return 0;
  if (parsed != 0) return 2;
  fsw_app::AppConfig app;
  std::string error;
  if (!fsw_app::load_app_config(o.config, &app, &error)) {
    std::fprintf(stderr, "hrlocalize: %s\n", error.c_str());
    return 2;
  }
  std::vector<Eigen::Isometry3d> handrails;
  if (!o.scenario.empty()) {
    sim_hal::Scenario sc;
    if (!sim_hal::load_scenario(o.scenario, &sc, &error)) {
      std::fprintf(stderr, "hrlocalize: --scenario: %s\n", error.c_str());
      return 2;
    }
    handrails = true_handrail_frames(sc);
    if (handrails.empty()) {
      std::fprintf(stderr, "hrlocalize: --scenario: %s has no handrail to score against\n",
                   o.scenario.c_str());
      return 2;
    }
  }
  lcm::LogFile log(o.log, "r");
  if (!log.good()) {
    std::fprintf(stderr, "hrlocalize: %s: cannot open as an LCM log (%s)\n", o.log.c_str(),
                 std::strerror(errno));
    return 2;
  }
  hal::ManualClock clock(0);
  // The log's messages are dated on the recorded run's clock: replayed,
  // their time and rate are not judged (their counters and content are).
  fsw_app::LcmHub hub("memq://", fsw_app::LcmHub::kReplay);
  fsw_app::LocalizationTask task(hub, fsw_app::localization_task_config(app), clock);
  const auto drain = [&hub] {
    while (hub.handle(0) > 0) {
    }
  };

  std::int64_t t0_us = -1;  // the first estimate's capture time (the robot's clock)
  bool have_truth = false;
  Eigen::Isometry3d T_true = Eigen::Isometry3d::Identity();
  Stat err_held, err_all, across_held, along_held;
  long inputs = 0, estimates = 0, bad_estimates = 0, events = 0;
  long verdicts[loc::kNumUpdateStatus] = {};
  if (!o.quiet) {
    // World axes, or with a scenario the handrail's: out, across, along.
    const bool rel = !handrails.empty();
    std::printf("%8s %-3s %-24s %5s %5s %11s %8s %8s %8s\n", "t s", "st", "verdict", "used",
                "gated", "nis/dof", rel ? "out mm" : "x mm", rel ? "across" : "y mm",
                rel ? "along" : "z mm");
  }
  for (const lcm::LogEvent* e = log.readNextEvent(); e != nullptr; e = log.readNextEvent()) {
    ++events;
    if (e->channel == fsw_app::channel::kTruthPose) {
      hrp::robot_pose_t m;
      if (m.decode(e->data, 0, e->datalen) >= 0) {
        T_true = fsw_app::from_msg(m.T_world_body);
        have_truth = T_true.matrix().allFinite();
      }
      continue;
    }
    if (!is_input(e->channel)) continue;
    ++inputs;
    // The log's timestamps are the logger's clock, not the robot's; the
    // task reads its clock only to pace its health messages.
    if (e->timestamp > clock.now_us()) clock.set_us(e->timestamp);
    hrp::handrail_estimate_t est{};
    const bool is_estimate = e->channel == fsw_app::channel::kHandrailEstimate;
    if (is_estimate && est.decode(e->data, 0, e->datalen) < 0) {
      ++bad_estimates;
      std::fprintf(stderr, "hrlocalize: %s: event %lld on %s does not decode; skipped\n",
                   o.log.c_str(), static_cast<long long>(e->eventnum), e->channel.c_str());
      continue;
    }
    const std::array<std::uint32_t, 2 * loc::kNumUpdateStatus> before = handrail_counts(task);
    (void)hub.publish_raw(e->channel, static_cast<const std::uint8_t*>(e->data),
                          static_cast<std::size_t>(e->datalen));
    drain();
    task.step();
    drain();
    const loc::PoseEstimate pose = task.filter().estimate();
    Eigen::Vector3d err_mm = 1e3 * (pose.p_world_body_m - T_true.translation());
    const bool scored = have_truth && pose.initialized;
    if (scored) {
      err_all.add(err_mm.norm());
      if (pose.handrail_holding) err_held.add(err_mm.norm());
    }
    const loc::HandrailMap map = task.filter().handrail_map();
    if (scored && !handrails.empty()) {
      Eigen::Isometry3d T_est = Eigen::Isometry3d::Identity();
      T_est.linear() = pose.q_world_body.normalized().toRotationMatrix();
      T_est.translation() = pose.p_world_body_m;
      // Before a map there is nothing to be relative to: the line shows "-".
      err_mm = map.valid ? Eigen::Vector3d(1e3 * relative_error_m(handrails, map, T_est, T_true))
                         : Eigen::Vector3d::Constant(std::nan(""));
      if (map.valid && pose.handrail_holding) {
        across_held.add(std::hypot(err_mm.x(), err_mm.y()));
        along_held.add(std::fabs(err_mm.z()));
      }
    }
    if (!is_estimate) continue;
    ++estimates;
    if (t0_us < 0) t0_us = est.capture_utime;
    const loc::UpdateResult& u = task.filter().last_update();
    // The filter's verdict is the status whose count this estimate moved;
    // none moved when the task found it unusable (NH, a missed deadline,
    // too little in view), and last_update() is then an older one's.
    const std::array<std::uint32_t, 2 * loc::kNumUpdateStatus> after = handrail_counts(task);
    int status = -1;
    for (int k = 0; k < 2 * loc::kNumUpdateStatus; ++k) {
      if (after[static_cast<std::size_t>(k)] != before[static_cast<std::size_t>(k)]) {
        status = k % loc::kNumUpdateStatus;
      }
    }
    const char* verdict =
        status >= 0 ? loc::to_string(static_cast<loc::UpdateStatus>(status)) : "NOT_USED";
    if (status >= 0) ++verdicts[status];
    if (o.quiet) continue;
    const double t_s = 1e-6 * static_cast<double>(est.capture_utime - t0_us);
    if (scored && err_mm.allFinite()) {
      std::printf("%8.2f %-3s %-24s %5d %5d %5.1f/%-5d %+8.1f %+8.1f %+8.1f\n", t_s,
                  state_name(est.state), verdict, u.features_used, u.features_gated, u.nis, u.dof,
                  err_mm.x(), err_mm.y(), err_mm.z());
    } else {
      std::printf("%8.2f %-3s %-24s %5d %5d %5.1f/%-5d %8s %8s %8s\n", t_s, state_name(est.state),
                  verdict, u.features_used, u.features_gated, u.nis, u.dof, "-", "-", "-");
    }
  }
  const fsw_app::LocalizerReport r = fsw_app::localizer_report(task);
  std::printf(
      "\n%s: %ld events, %ld localizer inputs (%llu IMU, %llu GP, %ld handrail estimates)\n",
      o.log.c_str(), events, inputs, static_cast<unsigned long long>(r.task.imu_in),
      static_cast<unsigned long long>(r.task.gp_in), estimates);
  std::printf("handrail updates:");
  for (int s = 0; s < loc::kNumUpdateStatus; ++s) {
    if (verdicts[s] > 0) {
      std::printf(" %s %ld", loc::to_string(static_cast<loc::UpdateStatus>(s)), verdicts[s]);
    }
  }
  std::printf("\nGP poses: %u accepted, %llu held off while the handrail held, %u gated\n",
              r.gp_accepted, static_cast<unsigned long long>(r.task.gp_held_off),
              r.gp_rejected_gate);
  if (err_all.n > 0) {
    std::printf(
        "position error against the truth: while the handrail held mean %.1f mm, max %.1f mm "
        "(%ld poses); over the run mean %.1f mm, max %.1f mm\n",
        err_held.mean(), err_held.max, err_held.n, err_all.mean(), err_all.max);
  } else {
    std::printf("position error: no %s in the log to score against\n",
                fsw_app::channel::kTruthPose);
  }
  if (across_held.n > 0) {
    std::printf(
        "relative to the handrail, while it held: across the bar mean %.1f mm, max %.1f mm; "
        "along it mean %.1f mm, max %.1f mm (%ld poses)\n",
        across_held.mean(), across_held.max, along_held.mean(), along_held.max, across_held.n);
  }
  if (inputs == 0) {
    std::fprintf(stderr,
                 "hrlocalize: %s holds no %s, %s or %s message (record the run with fsw_app "
                 "--log LOG)\n",
                 o.log.c_str(), fsw_app::channel::kImuSample, fsw_app::channel::kGpPose,
                 fsw_app::channel::kHandrailEstimate);
    return 1;
  }
  return bad_estimates > 0 ? 1 : 0;
}
