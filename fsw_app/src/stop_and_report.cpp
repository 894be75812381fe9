#include "stop_and_report.hpp"

#include <chrono>
#include <cstdio>
#include <string>
#include <thread>

#include "run_signals.hpp"
#include "run_summary.hpp"
#ifdef HRP_WITH_SIM
#include "hil_world.hpp"
#endif

namespace fsw_app {

int stop_and_report(const Options& opt, LcmHub& hub, const hal::Clock& clock, RunWatch& watch,
                    RunTasks& tasks, ArmLinks& links, CameraSource& frames, HilWorld* world,
                    RunLog& log, const RunOutcome& outcome) {
#ifndef HRP_WITH_SIM
  (void)world;
#endif
  RunSummary summary;
  if (tasks.arm_task) {
    summary.arm_loop = tasks.arm_task->cycle_stats();
    summary.servo_bus = links.bus->counters();
    summary.gripper_retries = links.board->retries_used();
  }
  if (tasks.camera_task) {
    summary.camera_longest_gap_ms = 1e-3 * static_cast<double>(tasks.camera_task->longest_gap_us());
  }
  summary.camera_path = opt.camera_path();
  if (tasks.estimator_task) {
    summary.estimator_longest_latency_ms =
        1e-3 * static_cast<double>(tasks.estimator_task->counters().longest_latency_us);
    const EstimatorCounters c = tasks.estimator_task->counters();
    summary.estimator_frames_without_pose = static_cast<long long>(c.without_pose);
    summary.without_pose_reasons_json = "{";
    for (int k = 0; k < kPoseAtStatusCount; ++k) {
      const std::uint64_t n = c.without_pose_by_status[static_cast<std::size_t>(k)];
      if (n == 0) continue;
      const std::string name = to_string(static_cast<PoseAtStatus>(k));
      const std::string count = std::to_string(n);
      const bool first = summary.without_pose_reasons.empty();
      summary.without_pose_reasons += (first ? "" : ", ") + name + " " + count;
      summary.without_pose_reasons_json += (first ? "\"" : ", \"") + name + "\": " + count;
    }
    summary.without_pose_reasons_json += "}";
  }
  if (tasks.player) tasks.player->stop();
  if (tasks.manager) {
    tasks.manager->stop();
    summary.camera_watch = tasks.manager->controller().camera_watch();
  }
  if (tasks.arm_task) tasks.arm_task->stop();
  // The driver's state as the run ended, before stopping puts it back to
  // OPEN; the counts after the stop, complete.
  frames.report(&summary);
  const std::string usb_state_at_end = summary.usb ? summary.usb->state : std::string();
  const std::string usb_health_at_end = summary.usb ? summary.usb->health : std::string();
  if (frames.camera()) (void)frames.camera()->stop_capture();
  frames.report(&summary);
  if (summary.usb && !usb_state_at_end.empty()) {
    summary.usb->state = usb_state_at_end;
    summary.usb->health = usb_health_at_end;
  }
  if (tasks.estimator_task) {
    tasks.estimator_task->stop();
    tasks.estimator_task->publish_health();
  }
  if (tasks.localizer) {
    tasks.localizer->stop();
    tasks.localizer->publish_health();
    summary.localizer = localizer_report(*tasks.localizer);
  }
  watch.input_health.publish(clock.now_us());
  // Time for the last health messages to reach this process's mailboxes
  // (and the log) before the dispatcher stops.
  std::this_thread::sleep_for(std::chrono::milliseconds(100));
  hub.stop();
  summary.inputs = watch.input_health.refresh(clock.now_us());
  summary.receiver_faults = hub.receiver_faults();

  watch.health_box.read(&summary.health);
  watch.arm_box.read(&summary.arm);
  {
    // Reported where an estimator ran here or its estimates were heard.
    const SightingReport heard = watch.sightings.report();
    std::uint64_t total = heard.counts.rejected;
    for (std::uint64_t n : heard.counts.by_state) total += n;
    if (tasks.estimator_task || total > 0) summary.sightings = heard;
  }
#ifdef HRP_WITH_SIM
  if (world) {
    summary.grasp_error_m = world->stats().grasp_error_m;
    summary.grasp_along_m = world->stats().grasp_along_m;
    summary.localization = world->stats().localization;
    world->stop();
  }
#endif
  if (tasks.player) summary.replay = tasks.player->counts();
  summary.stop = outcome.stop;
  if (run_signals::stop_signal() && !outcome.stop.stopped) {
    summary.stop.stopped = true;  // a run without a perch to stop safely
    summary.stop.signal = run_signals::stop_signal();
    summary.stop.at_rest = true;
  }
  summary.perched = outcome.perched;
  summary.time_to_perch_s = outcome.perched ? outcome.perched_s - outcome.perch_cmd_s : -1.0;
  summary.success =
      outcome.perched && summary.grasp_error_m >= 0.0 && summary.grasp_error_m <= 0.01;
  const bool log_complete = log.close();
  summary.log_messages = log.events();
  summary.log_depth_frames = log.depth_frames();
  summary.log_lost = log.lost();
  summary.log_failure = log.failure();
  if (tasks.frame_publisher)
    summary.frames_published = static_cast<std::int64_t>(tasks.frame_publisher->published());
  int rc = 0;
  if (opt.perch) {
    print_perch_summary(opt, summary, stdout);
    rc = summary.stop.stopped ? 128 + summary.stop.signal : (summary.success ? 0 : 1);
  } else if (tasks.player) {
    print_replay_summary(opt, summary, stdout);
  }
  if (!opt.summary_json.empty() && !write_summary_json(opt, summary, opt.summary_json)) {
    std::fprintf(stderr, "fsw_app: %s: cannot write the summary\n", opt.summary_json.c_str());
    return 1;
  }
  if (!log_complete) {
    std::fprintf(stderr, "fsw_app: LCM log %s: %s; %lld messages not recorded\n", opt.log.c_str(),
                 summary.log_failure.c_str(), static_cast<long long>(summary.log_lost));
    return kExitLogIncomplete;
  }
  return rc;
}

}  // namespace fsw_app
