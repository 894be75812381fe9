#include "run_until_done.hpp"

#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>
#include <thread>

#include "arm/perch_types.hpp"
#include "hal/realtime.hpp"
#include "run_signals.hpp"
#ifdef HRP_WITH_SIM
#include "inject_fault.hpp"
#endif

namespace fsw_app {

namespace {

// The arm states in which nothing moves: where a safe stop may end.
bool arm_at_rest(std::int8_t state) {
  return state == hrp::arm_state_t::INIT || state == hrp::arm_state_t::STOWED ||
         state == hrp::arm_state_t::PERCHED || state == hrp::arm_state_t::FAULT;
}
// The sequence numbers of this program's two commands, so that the arm's
// last_command_sequence tells which one it has taken.
constexpr std::int32_t kPerchSequence = 1;
constexpr std::int32_t kStopSequence = 2;
// How long a safe stop may take: an ABORT during the approach opens, backs
// off and stows (about 10 s in the simulator).
constexpr double kSafeStopLimit_s = 30.0;
// How long the arm may take to come to rest after a fault (folding from the
// grip posture takes about 2 s at the configured joint speed).
constexpr double kFaultSettleLimit_s = 8.0;

const char* state_name(std::int8_t s) {
  return arm::to_string(static_cast<arm::PerchState>(s));
}

}  // namespace

RunOutcome run_until_done(const Options& opt, const AppConfig& cfg, const hal::Clock& clock,
                          RunWatch& watch, RunTasks& tasks, CameraSource& frames, HilWorld* world) {
#ifndef HRP_WITH_SIM
  (void)world;
#endif
  LcmDepthCamera* lcm_camera = frames.lcm_camera();
  const bool tty = isatty(STDERR_FILENO) && !opt.quiet;
  const auto t0 = std::chrono::steady_clock::now();
  auto seconds = [&] {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  };
  RunOutcome out;
  hrp::arm_state_t arm{};
  hrp::approach_status_t approach{};
  bool commanded = false, approach_started = false, done = false;
  double last_print = -10.0, replay_done_s = -1.0;
  double fault_s = -1.0;
  std::uint64_t rejections_reported = 0;
#ifdef HRP_WITH_SIM
  double approach_s = 0.0;
  std::size_t next_fault = 0;
  std::string error;
#endif
  bool realtime_reported = false;
  double last_input_health = 0.0;
  bool stopping = false;
  double stop_s = 0.0;
  while (!done) {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    const double t = seconds();
    if (t - last_input_health >= 1.0) {
      last_input_health = t;
      watch.input_health.publish(clock.now_us());
    }
    if (tasks.arm_task && !realtime_reported && cfg.arm_rt_priority > 0 &&
        tasks.arm_task->cycle_stats().cycles > 0) {
      realtime_reported = true;
      const hal::RealtimeStatus rt = tasks.arm_task->cycle_stats().realtime;
      if (rt != hal::RealtimeStatus::kGranted) {
        std::fprintf(stderr,
                     "fsw_app: arm loop: SCHED_FIFO priority %d %s; it runs under the normal "
                     "scheduler (run as root, grant CAP_SYS_NICE, or set an rtprio limit)\n",
                     cfg.arm_rt_priority, hal::to_string(rt));
      }
    }
    if (lcm_camera && lcm_camera->messages_rejected() > rejections_reported) {
      rejections_reported = lcm_camera->messages_rejected();
      std::fprintf(stderr, "%sfsw_app: DEPTH_FRAME message dropped: %s (%llu so far)\n",
                   tty ? "\n" : "", to_string(lcm_camera->last_rejection()),
                   static_cast<unsigned long long>(rejections_reported));
    }
    const bool have_arm = watch.arm_box.read(&arm) != 0;
    watch.approach_box.read(&approach);
    if (run_signals::stop_signal() && !stopping) {
      // Only a perch has something to stop safely; any other run ends here.
      if (!opt.perch || !commanded) break;
      stopping = true;
      stop_s = t;
      hrp::perch_command_t c{};
      c.utime = clock.now_us();
      c.sequence = kStopSequence;
      c.command = hrp::perch_command_t::ABORT;
      watch.command_pub.publish(c);
      std::fprintf(stderr,
                   "%sfsw_app: %s at %.1f s (arm %s): ABORT sent, waiting for the arm to come to "
                   "rest; a second signal ends the program at once\n",
                   tty ? "\n" : "", signal_name(run_signals::stop_signal()), t,
                   have_arm ? state_name(arm.state) : "-");
    }
    if (stopping) {
      const bool acknowledged = arm.last_command_sequence == kStopSequence;
      if ((acknowledged && arm_at_rest(arm.state)) || t - stop_s > kSafeStopLimit_s) {
        out.stop.stopped = true;
        out.stop.signal = run_signals::stop_signal();
        out.stop.at_rest = acknowledged && arm_at_rest(arm.state);
        out.stop.after_s = t - stop_s;
        done = true;
      }
    }
    if (opt.perch && !commanded && !stopping && have_arm && arm.state == hrp::arm_state_t::STOWED) {
      hrp::perch_command_t c{};
      c.utime = clock.now_us();
      c.sequence = kPerchSequence;
      c.command = hrp::perch_command_t::PERCH;
      watch.command_pub.publish(c);
      commanded = true;
      out.perch_cmd_s = t;
    }
    if (have_arm && arm.state == hrp::arm_state_t::GRIPPER_OPEN && !approach_started) {
      approach_started = true;
#ifdef HRP_WITH_SIM
      approach_s = t;
      if (world) world->sensors().begin_scoring();
#endif
    }
#ifdef HRP_WITH_SIM
    // Faults, timed from the start of the approach.
    while (world && approach_started && next_fault < opt.faults.size() &&
           t >= approach_s + opt.faults[next_fault].second) {
      const std::string& f = opt.faults[next_fault++].first;
      std::fprintf(stderr, "\nfsw_app: fault injected at %.1f s: %s\n", t, f.c_str());
      inject_fault(f, clock, *world, frames, tasks.camera_cut.get());
    }
    if (frames.hil_usb() && !frames.hil_usb()->service(clock.now_us(), &error)) {
      std::fprintf(stderr, "\nfsw_app: the emulated camera would not plug back in: %s\n",
                   error.c_str());
    }
#endif
    if (opt.perch && commanded && !stopping) {
      if (arm.state == hrp::arm_state_t::PERCHED && out.perched_s == 0.0) out.perched_s = t;
      if (out.perched_s > 0.0 && t - out.perched_s > 1.0) {
        out.perched = true;
        done = true;
      }
      // A fault ends the run once the arm has come to rest (POSE_LOST and
      // CAMERA_LOST fold it), so that the summary reports where it ended up.
      if (arm.state == hrp::arm_state_t::FAULT) {
        if (fault_s < 0.0) fault_s = t;
        // A few arm cycles first: the state that entered FAULT was read
        // before any safe-state motion began.
        if ((t - fault_s > 0.3 && !arm.joints_moving) || t - fault_s > kFaultSettleLimit_s) {
          done = true;
        }
      }
      if (t - out.perch_cmd_s > opt.timeout_s) done = true;
    }
    // A replay ends half a second after its last frame, time for the
    // estimator to finish it.
    if (tasks.player && tasks.player->finished()) {
      if (replay_done_s < 0.0) replay_done_s = t;
      if (t - replay_done_s > 0.5) done = true;
    }
    if (!opt.perch && opt.duration_s > 0 && t > opt.duration_s) done = true;
    if (!opt.quiet && (tty || t - last_print >= 2.0)) {
      last_print = t;
      if (tasks.player) {
        std::fprintf(stderr, "%s%6.1f s  replayed %llu of %llu frames%s", tty ? "\r" : "", t,
                     static_cast<unsigned long long>(tasks.player->counts().frames),
                     static_cast<unsigned long long>(tasks.player->frames_in_log()),
                     tty ? "   " : "\n");
      } else {
        std::fprintf(stderr, "%s%6.1f s  arm %-12s  target %s  error %6.3f m %5.1f deg%s",
                     tty ? "\r" : "", t, have_arm ? state_name(arm.state) : "-",
                     approach.utime ? "seen" : "none", approach.position_error_m,
                     approach.angle_error_rad * 180.0 / M_PI, tty ? "   " : "\n");
      }
    }
  }
  if (tty) std::fprintf(stderr, "\n");
  return out;
}

}  // namespace fsw_app
