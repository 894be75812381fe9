// fsw_app: the perching flight software. By default one process with a
// thread per task (camera, estimator, arm, perch manager), talking over
// LCM; --tasks runs a subset, the rest running in other processes.
//
//   fsw_app --hal sim --scenario FILE [--perch] ...   hardware-in-loop on the simulated HAL
//   fsw_app --hal sim --camera usb ...                the same through the USB driver
//   fsw_app --hal real [--camera-replay DIR] ...      robot ports; the Pico Flexx or frames
//   fsw_app --frames-from-log RUN.lcmlog ...          a recorded run into the estimator
//
// With --perch it commands PERCH, shows progress, and ends with a summary
// (and exit status 0 only for a perch within 1 cm of the bar).
#include <signal.h>
#include <unistd.h>

#include <lcm/lcm-cpp.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <mutex>
#include <string>
#include <thread>

#include "app_options.hpp"
#include "arm_io/ax12_joints.hpp"
#include "arm_io/gripper_actuator.hpp"
#include "arm_links.hpp"
#include "camera_source.hpp"
#include "dynamixel/bus.hpp"
#include "frame_receive_buffer.hpp"
#include "fsw_app/app_config.hpp"
#include "fsw_app/arm_task.hpp"
#include "fsw_app/camera_task.hpp"
#include "fsw_app/estimator_task.hpp"
#include "fsw_app/frame_publisher.hpp"
#include "fsw_app/input_health.hpp"
#include "fsw_app/lcm_depth_camera.hpp"
#include "fsw_app/lcm_hub.hpp"
#include "fsw_app/localization_task.hpp"
#include "fsw_app/log_player.hpp"
#include "fsw_app/perch_manager.hpp"
#include "gripper/gripper_board.hpp"
#include "hal/linux_serial_port.hpp"
#include "hal/realtime.hpp"
#include "hal/use_case.hpp"
#include "run_log.hpp"
#include "run_signals.hpp"
#include "run_summary.hpp"
#ifdef HRP_WITH_SIM
#include "hil_world.hpp"
#include "sim_hal/scenario.hpp"
#include "sim_hal/umockdev_preload.hpp"
#endif

namespace {

using fsw_app::Options;

// The arm states in which nothing moves: where a safe stop may end.
bool arm_at_rest(std::int8_t state) {
  return state == hrp::arm_state_t::INIT || state == hrp::arm_state_t::STOWED ||
         state == hrp::arm_state_t::PERCHED || state == hrp::arm_state_t::FAULT;
}
constexpr std::int32_t kPerchSequence = 1;
constexpr std::int32_t kStopSequence = 2;
// How long a safe stop may take: an ABORT during the approach opens, backs
// off and stows (about 10 s in the simulator).
constexpr double kSafeStopLimit_s = 30.0;
// How long the arm may take to come to rest after a fault (folding from the
// grip posture takes about 2 s at the configured joint speed).
constexpr double kFaultSettleLimit_s = 8.0;

// Frames of 0.73 MB arrive over udpm as a dozen datagrams at once: with the
// kernel's default receive buffer (about 200 kB) most frames lose one. An
// estimator fed over udpm asks LCM for a 4 MB buffer unless the URL names
// one, and says so when the kernel will not grant that much.
const char* state_name(std::int8_t s) {
  return arm::to_string(static_cast<arm::PerchState>(s));
}

}  // namespace

int main(int argc, char** argv) {
  run_signals::install();
  Options opt;
  if (auto rc = fsw_app::parse_options(argc, argv, &opt)) return *rc;
#ifdef HRP_WITH_SIM
  // The emulated USB camera lives in this process and needs umockdev's
  // preload library under it: the program starts itself again with it.
  if (opt.emulated_usb_camera()) {
    sim_hal::umockdev_preload::ensure(argv);
  }
#endif

  fsw_app::AppConfig cfg;
  std::string error;
  if (!fsw_app::load_app_config(opt.config, &cfg, &error)) {
    std::fprintf(stderr, "fsw_app: %s\n", error.c_str());
    return 2;
  }
  if (!opt.lcm_url.empty()) cfg.lcm_url = opt.lcm_url;
  const bool sends_frames = (opt.runs(fsw_app::kCameraTask) &&
                             (opt.publish_frames || !opt.runs(fsw_app::kEstimatorTask))) ||
                            !opt.frames_from_log.empty();
  const bool estimator_fed_over_lcm = opt.runs(fsw_app::kEstimatorTask) &&
                                      !opt.runs(fsw_app::kCameraTask) &&
                                      opt.frames_from_log.empty();
  if (estimator_fed_over_lcm || (!opt.log.empty() && sends_frames)) {
    if (!fsw_app::with_frame_receive_buffer(&cfg.lcm_url, &error)) {
      if (!opt.log.empty() && sends_frames) {
        // Recording frames that would be lost is refused outright.
        std::fprintf(stderr,
                     "fsw_app: %s; or record in-process with --lcm-url memq:// (--log "
                     "still records every message)\n",
                     error.c_str());
        return 2;
      }
      std::fprintf(stderr, "fsw_app: %s\n", error.c_str());
    }
  }
  if (!opt.handrail.empty()) {
    const float length = cfg.estimator.handrail.bar_length_m;
    cfg.estimator.handrail = opt.handrail == "iss" ? estimator::iss_handrail(length)
                                                   : estimator::paper_round_handrail(length);
  }
  if (!opt.arm_port.empty()) cfg.ports.servo_port = opt.arm_port;
  if (!opt.gripper_port.empty()) cfg.ports.gripper_port = opt.gripper_port;
  const hal::UseCase* use_case = hal::find_use_case(cfg.use_case);

  auto hub_owner = std::make_unique<fsw_app::LcmHub>(cfg.lcm_url);
  if (!hub_owner->good() && opt.hal == "sim" && opt.tasks == fsw_app::kAllTasks &&
      opt.lcm_url.empty()) {
    // A hardware-in-loop run with every task in this process needs no
    // network: on a machine without a multicast route (a container, no
    // default route) it runs in-process rather than not at all. Never on
    // the robot (--hal real), and never when the URL was asked for.
    std::fprintf(stderr,
                 "fsw_app: LCM would not start on %s (no multicast route?); every task of this "
                 "run is in this process, so it runs on memq:// instead. To watch it with "
                 "lcm-spy, add the route: sudo ip link set lo multicast on; sudo ip route add "
                 "224.0.0.0/4 dev lo\n",
                 cfg.lcm_url.c_str());
    cfg.lcm_url = "memq://";
    hub_owner = std::make_unique<fsw_app::LcmHub>(cfg.lcm_url);
  }
  fsw_app::LcmHub& hub = *hub_owner;
  if (!hub.good()) {
    std::fprintf(stderr,
                 "fsw_app: LCM would not start on %s. For udpm on one host add the multicast "
                 "route: sudo ip link set lo multicast on; sudo ip route add 224.0.0.0/4 dev lo\n",
                 cfg.lcm_url.c_str());
    return 1;
  }
  fsw_app::RunLog log;
  if (!opt.log.empty()) {
    if (!log.open(opt.log, &error)) {
      std::fprintf(stderr, "fsw_app: %s\n", error.c_str());
      return 1;
    }
    hub.subscribe_all(&fsw_app::RunLog::sink, &log);
  }
  hal::MonotonicClock clock;
  const bool sim = opt.hal == "sim";

  // --- The simulated world, when a task here needs its camera or devices.
  std::string servo_port = cfg.ports.servo_port, gripper_port = cfg.ports.gripper_port;
#ifdef HRP_WITH_SIM
  sim_hal::Scenario scenario;
  std::unique_ptr<fsw_app::HilWorld> world;
  if (opt.needs_sim_world()) {
    if (!sim_hal::load_scenario(opt.scenario, &scenario, &error)) {
      std::fprintf(stderr, "fsw_app: %s\n", error.c_str());
      return 2;
    }
    world = std::make_unique<fsw_app::HilWorld>(
        hub, scenario, cfg, fsw_app::hil_start_pose(scenario, cfg.T_body_cam, opt.seed), opt.seed,
        clock, fsw_app::hil_sensor_params(opt.gp_bias_m, opt.gp_bias_deg));
    if (!world->start(&error)) {
      std::fprintf(stderr, "fsw_app: simulated devices: %s\n", error.c_str());
      return 1;
    }
    servo_port = world->servo_path();
    gripper_port = world->gripper_path();
    if (!opt.runs(fsw_app::kArmTask)) {
      std::fprintf(stderr,
                   "fsw_app: simulated servos on %s, gripper board on %s (for an arm task in "
                   "another process: --hal real --tasks arm --arm-port %s --gripper-port %s)\n",
                   servo_port.c_str(), gripper_port.c_str(), servo_port.c_str(),
                   gripper_port.c_str());
    }
  }
#else
  if (opt.needs_sim_world()) {
    std::fprintf(stderr,
                 "fsw_app: this build has no simulated HAL (a robot build); use --hal real\n");
    return 2;
  }
#endif

  // --- Where frames come from (camera_source.hpp).
  fsw_app::CameraSource frames;
#ifdef HRP_WITH_SIM
  if (auto rc = fsw_app::open_camera_source(opt, cfg, hub, world.get(), &scenario, clock, &frames))
    return *rc;
#else
  if (auto rc = fsw_app::open_camera_source(opt, cfg, hub, nullptr, nullptr, clock, &frames))
    return *rc;
#endif
  hal::DepthCamera* camera = frames.camera();
  fsw_app::LcmDepthCamera* lcm_camera = frames.lcm_camera();

  // --- The arm's drivers on the ports.
  fsw_app::ArmLinks links;
  if (opt.runs(fsw_app::kArmTask) &&
      !fsw_app::open_arm_links(cfg, servo_port, gripper_port, sim, clock, &links)) {
    return 1;
  }

  // --- The tasks.
  std::uint32_t max_w = 0, max_h = 0;
  std::unique_ptr<fsw_app::FrameRing> ring;
  std::unique_ptr<fsw_app::CameraTask> camera_task;
  std::unique_ptr<fsw_app::FramePublisher> frame_publisher;
  std::unique_ptr<fsw_app::EstimatorTask> estimator_task;
  if (camera) {
    const hal::CameraStatus init = camera->initialize();
    if (init != hal::CameraStatus::kSuccess) {
      const std::string detail = frames.failure_detail();
      std::fprintf(stderr, "fsw_app: the camera would not initialize: %s%s%s\n",
                   hal::to_string(init), detail.empty() ? "" : ": ", detail.c_str());
      return 1;
    }
    if (camera->set_use_case(cfg.use_case.c_str()) != hal::CameraStatus::kSuccess ||
        camera->max_frame_size(&max_w, &max_h) != hal::CameraStatus::kSuccess) {
      std::fprintf(stderr, "fsw_app: the camera would not take use case %s\n",
                   cfg.use_case.c_str());
      return 1;
    }
    const hal::CameraStatus configured = frames.configure_after_use_case();
    if (configured != hal::CameraStatus::kSuccess) {
      std::fprintf(stderr, "fsw_app: the camera would not take automatic exposure: %s\n",
                   hal::to_string(configured));
      return 1;
    }
    ring = std::make_unique<fsw_app::FrameRing>(3, max_w, max_h);
    camera_task = std::make_unique<fsw_app::CameraTask>(*ring, max_w, max_h);
    if (lcm_camera == nullptr && (opt.publish_frames || !opt.runs(fsw_app::kEstimatorTask))) {
      frame_publisher =
          std::make_unique<fsw_app::FramePublisher>(hub, clock, max_w, max_h, *camera_task);
    }
  }
  if (opt.runs(fsw_app::kEstimatorTask)) {
    fsw_app::EstimatorTaskConfig est_cfg;
    est_cfg.detector = cfg.estimator;
    est_cfg.detector.budget_us =
        opt.budget_us > 0 ? opt.budget_us : hal::frame_period_us(*use_case);
    est_cfg.T_body_cam = cfg.T_body_cam;
    est_cfg.arm = cfg.perch.geometry;
    est_cfg.max_width = max_w;
    est_cfg.max_height = max_h;
    estimator_task =
        std::make_unique<fsw_app::EstimatorTask>(hub, *camera_task, *ring, est_cfg, clock);
  }
  std::unique_ptr<fsw_app::ArmTask> arm_task;
  if (opt.runs(fsw_app::kArmTask)) {
    arm_task = std::make_unique<fsw_app::ArmTask>(hub, *links.joints, *links.gripper, cfg.perch,
                                                  clock, cfg.arm_rate_hz, cfg.arm_rt_priority);
  }
  std::unique_ptr<fsw_app::PerchManager> manager;
  if (opt.runs(fsw_app::kManagerTask)) {
    const Eigen::Vector3d p_body_grasp =
        arm::forward_kinematics(cfg.perch.geometry, cfg.perch.geometry.grip).translation();
    manager = std::make_unique<fsw_app::PerchManager>(hub, cfg.approach, p_body_grasp, clock,
                                                      cfg.manager_rate_hz);
  }
  std::unique_ptr<fsw_app::LocalizationTask> localizer;
  if (opt.runs(fsw_app::kLocalizerTask)) {
    localizer = std::make_unique<fsw_app::LocalizationTask>(
        hub, fsw_app::localization_task_config(cfg), clock);
  }
  std::unique_ptr<fsw_app::LogPlayer> player;
  if (!opt.frames_from_log.empty()) {
    player = std::make_unique<fsw_app::LogPlayer>(hub, opt.frames_from_log, clock, max_w, max_h);
    if (!player->open(&error)) {
      std::fprintf(stderr, "fsw_app: --frames-from-log %s\n", error.c_str());
      return 2;
    }
  }
#ifdef HRP_WITH_SIM
  // The in-process cameras' stop for --fault camera-silent / camera-lost
  // (over USB the cable is pulled instead, for the driver to find again).
  std::unique_ptr<fsw_app::CameraCut> camera_cut;
#endif
  if (camera) {
    hal::DepthDataListener* listener = camera_task.get();
    if (frame_publisher) listener = frame_publisher.get();
#ifdef HRP_WITH_SIM
    if (world && !frames.hil_usb()) {
      camera_cut = std::make_unique<fsw_app::CameraCut>(clock, *listener);
      listener = camera_cut.get();
    }
#endif
    if (camera->register_data_listener(listener) != hal::CameraStatus::kSuccess ||
        camera->start_capture() != hal::CameraStatus::kSuccess) {
      std::fprintf(stderr, "fsw_app: the camera would not start capturing\n");
      return 1;
    }
  }

  // --- What the run watches, over LCM like any other reader.
  fsw_app::Mailbox<hrp::arm_state_t> arm_box;
  fsw_app::Mailbox<hrp::estimator_health_t> health_box;
  fsw_app::Mailbox<hrp::approach_status_t> approach_box;
  hub.subscribe(fsw_app::channel::kArmState, &arm_box);
  hub.subscribe(fsw_app::channel::kEstimatorHealth, &health_box);
  hub.subscribe(fsw_app::channel::kApproachStatus, &approach_box);
  // Every estimate, wherever the estimator runs: the summary's sightings.
  fsw_app::SightingTally sightings(cfg.estimator);
  hub.subscribe(fsw_app::channel::kHandrailEstimate, &sightings);
  fsw_app::Publisher<hrp::perch_command_t> command_pub(hub, fsw_app::channel::kPerchCommand);
  // Every subscription is made by now: the channel list is fixed.
  fsw_app::InputHealthReporter input_health(hub, fsw_app::task_names(opt.tasks));

  run_signals::mark_tasks_running();
  hub.start();
  if (localizer) localizer->start();
  if (estimator_task) estimator_task->start();
  if (arm_task) arm_task->start();
  if (manager) manager->start();
  if (player) player->start();

  // --- The run.
  const bool tty = isatty(STDERR_FILENO) && !opt.quiet;
  const auto t0 = std::chrono::steady_clock::now();
  auto seconds = [&] {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  };
  hrp::arm_state_t arm{};
  hrp::approach_status_t approach{};
  bool commanded = false, approach_started = false, done = false, perched = false;
  double perch_cmd_s = 0.0, perched_s = 0.0, last_print = -10.0, replay_done_s = -1.0;
  double fault_s = -1.0;
  std::uint64_t rejections_reported = 0;
#ifdef HRP_WITH_SIM
  double approach_s = 0.0;
  std::size_t next_fault = 0;
#endif
  bool realtime_reported = false;
  double last_input_health = 0.0;
  bool stopping = false;
  double stop_s = 0.0;
  fsw_app::StopReport summary_stop;
  while (!done) {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    const double t = seconds();
    if (t - last_input_health >= 1.0) {
      last_input_health = t;
      input_health.publish(clock.now_us());
    }
    if (arm_task && !realtime_reported && cfg.arm_rt_priority > 0 &&
        arm_task->cycle_stats().cycles > 0) {
      realtime_reported = true;
      const hal::RealtimeStatus rt = arm_task->cycle_stats().realtime;
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
                   tty ? "\n" : "", fsw_app::to_string(lcm_camera->last_rejection()),
                   static_cast<unsigned long long>(rejections_reported));
    }
    const bool have_arm = arm_box.read(&arm) != 0;
    approach_box.read(&approach);
    if (run_signals::stop_signal() && !stopping) {
      // Only a perch has something to stop safely; any other run ends here.
      if (!opt.perch || !commanded) break;
      stopping = true;
      stop_s = t;
      hrp::perch_command_t c{};
      c.utime = clock.now_us();
      c.sequence = kStopSequence;
      c.command = hrp::perch_command_t::ABORT;
      command_pub.publish(c);
      std::fprintf(stderr,
                   "%sfsw_app: %s at %.1f s (arm %s): ABORT sent, waiting for the arm to come to "
                   "rest; a second signal ends the program at once\n",
                   tty ? "\n" : "", fsw_app::signal_name(run_signals::stop_signal()), t,
                   have_arm ? state_name(arm.state) : "-");
    }
    if (stopping) {
      const bool acknowledged = arm.last_command_sequence == kStopSequence;
      if ((acknowledged && arm_at_rest(arm.state)) || t - stop_s > kSafeStopLimit_s) {
        summary_stop.stopped = true;
        summary_stop.signal = run_signals::stop_signal();
        summary_stop.at_rest = acknowledged && arm_at_rest(arm.state);
        summary_stop.after_s = t - stop_s;
        done = true;
      }
    }
    if (opt.perch && !commanded && !stopping && have_arm && arm.state == hrp::arm_state_t::STOWED) {
      hrp::perch_command_t c{};
      c.utime = clock.now_us();
      c.sequence = kPerchSequence;
      c.command = hrp::perch_command_t::PERCH;
      command_pub.publish(c);
      commanded = true;
      perch_cmd_s = t;
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
      if (f == "servo-silent") {
        sim_hal::BusFaults silent;
        silent.no_reply = true;
        world->servos().set_faults(silent);
      } else if (f == "gripper-overcurrent") {
        world->gripper().set_winding_short(true);
      } else if (f == "occlude") {
        world->occlude_until(clock.now_us() + 1000000);
      } else if (f == "handrail-lost") {
        world->occlude_until(std::numeric_limits<std::int64_t>::max());
      } else if (f == "corrupt-frames") {
        // Over USB the frames are spoilt on the wire, where the driver
        // drops them; otherwise the camera task refuses them.
        if (frames.hil_usb()) {
          frames.hil_usb()->corrupt_next_frames(5);
        } else {
          world->corrupt_next_frames(5);
        }
      } else if (f == "imu-silent") {
        world->sensors().silence_imu_until(clock.now_us() + 500000);
      } else if (f == "imu-lost") {
        world->sensors().silence_imu_until(std::numeric_limits<std::int64_t>::max());
      } else if (f == "gp-jump") {
        world->sensors().jump_gp(Eigen::Vector3d(0.0, 0.2, 0.0));
      } else if (f == "usb-unplug") {
        frames.hil_usb()->unplug_for(clock.now_us(), 500000);
      } else if (f == "usb-stall") {
        frames.hil_usb()->stall_stream();
      } else if (f == "camera-silent" || f == "camera-lost") {
        const std::int64_t now_us = clock.now_us();
        const std::int64_t out_us =
            f == "camera-silent" ? 2000000 : std::numeric_limits<std::int64_t>::max() - now_us;
        if (frames.hil_usb()) {
          frames.hil_usb()->unplug_for(now_us, out_us);
        } else if (camera_cut) {
          camera_cut->cut_until(now_us + out_us);
        }
      }
    }
    if (frames.hil_usb() && !frames.hil_usb()->service(clock.now_us(), &error)) {
      std::fprintf(stderr, "\nfsw_app: the emulated camera would not plug back in: %s\n",
                   error.c_str());
    }
#endif
    if (opt.perch && commanded && !stopping) {
      if (arm.state == hrp::arm_state_t::PERCHED && perched_s == 0.0) perched_s = t;
      if (perched_s > 0.0 && t - perched_s > 1.0) {
        perched = true;
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
      if (t - perch_cmd_s > opt.timeout_s) done = true;
    }
    // A replay ends half a second after its last frame, time for the
    // estimator to finish it.
    if (player && player->finished()) {
      if (replay_done_s < 0.0) replay_done_s = t;
      if (t - replay_done_s > 0.5) done = true;
    }
    if (!opt.perch && opt.duration_s > 0 && t > opt.duration_s) done = true;
    if (!opt.quiet && (tty || t - last_print >= 2.0)) {
      last_print = t;
      if (player) {
        std::fprintf(stderr, "%s%6.1f s  replayed %llu of %llu frames%s", tty ? "\r" : "", t,
                     static_cast<unsigned long long>(player->counts().frames),
                     static_cast<unsigned long long>(player->frames_in_log()), tty ? "   " : "\n");
      } else {
        std::fprintf(stderr, "%s%6.1f s  arm %-12s  target %s  error %6.3f m %5.1f deg%s",
                     tty ? "\r" : "", t, have_arm ? state_name(arm.state) : "-",
                     approach.utime ? "seen" : "none", approach.position_error_m,
                     approach.angle_error_rad * 180.0 / M_PI, tty ? "   " : "\n");
      }
    }
  }
  if (tty) std::fprintf(stderr, "\n");

  // --- Stop, then report.
  fsw_app::RunSummary summary;
  if (arm_task) {
    summary.arm_loop = arm_task->cycle_stats();
    summary.servo_bus = links.bus->counters();
    summary.gripper_retries = links.board->retries_used();
  }
  if (camera_task) {
    summary.camera_longest_gap_ms = 1e-3 * static_cast<double>(camera_task->longest_gap_us());
  }
  summary.camera_path = opt.camera_path();
  if (estimator_task) {
    summary.estimator_longest_latency_ms =
        1e-3 * static_cast<double>(estimator_task->counters().longest_latency_us);
  }
  if (player) player->stop();
  if (manager) {
    manager->stop();
    summary.camera_watch = manager->controller().camera_watch();
  }
  if (arm_task) arm_task->stop();
  // The driver's state as the run ended, before stopping puts it back to
  // OPEN; the counts after the stop, complete.
  frames.report(&summary);
  const std::string usb_state_at_end = summary.usb ? summary.usb->state : std::string();
  const std::string usb_health_at_end = summary.usb ? summary.usb->health : std::string();
  if (camera) (void)camera->stop_capture();
  frames.report(&summary);
  if (summary.usb && !usb_state_at_end.empty()) {
    summary.usb->state = usb_state_at_end;
    summary.usb->health = usb_health_at_end;
  }
  if (estimator_task) {
    estimator_task->stop();
    estimator_task->publish_health();
  }
  if (localizer) {
    localizer->stop();
    localizer->publish_health();
    summary.localizer = fsw_app::localizer_report(*localizer);
  }
  input_health.publish(clock.now_us());
  std::this_thread::sleep_for(std::chrono::milliseconds(100));
  hub.stop();
  summary.inputs = input_health.refresh(clock.now_us());
  summary.receiver_faults = hub.receiver_faults();

  health_box.read(&summary.health);
  arm_box.read(&summary.arm);
  {
    // Reported where an estimator ran here or its estimates were heard.
    const fsw_app::SightingReport heard = sightings.report();
    std::uint64_t total = heard.counts.rejected;
    for (std::uint64_t n : heard.counts.by_state) total += n;
    if (estimator_task || total > 0) summary.sightings = heard;
  }
#ifdef HRP_WITH_SIM
  if (world) {
    summary.grasp_error_m = world->stats().grasp_error_m;
    summary.localization = world->stats().localization;
    world->stop();
  }
#endif
  if (player) summary.replay = player->counts();
  summary.stop = summary_stop;
  if (run_signals::stop_signal() && !summary_stop.stopped) {
    summary.stop.stopped = true;  // a run without a perch to stop safely
    summary.stop.signal = run_signals::stop_signal();
    summary.stop.at_rest = true;
  }
  summary.perched = perched;
  summary.time_to_perch_s = perched ? perched_s - perch_cmd_s : -1.0;
  summary.success = perched && summary.grasp_error_m >= 0.0 && summary.grasp_error_m <= 0.01;
  const bool log_complete = log.close();
  summary.log_messages = log.events();
  summary.log_depth_frames = log.depth_frames();
  summary.log_lost = log.lost();
  summary.log_failure = log.failure();
  if (frame_publisher)
    summary.frames_published = static_cast<std::int64_t>(frame_publisher->published());
  int rc = 0;
  if (opt.perch) {
    fsw_app::print_perch_summary(opt, summary, stdout);
    rc = summary.stop.stopped ? 128 + summary.stop.signal : (summary.success ? 0 : 1);
  } else if (player) {
    fsw_app::print_replay_summary(opt, summary, stdout);
  }
  if (!opt.summary_json.empty() && !fsw_app::write_summary_json(opt, summary, opt.summary_json)) {
    std::fprintf(stderr, "fsw_app: %s: cannot write the summary\n", opt.summary_json.c_str());
    return 1;
  }
  if (!log_complete) {
    std::fprintf(stderr, "fsw_app: LCM log %s: %s; %lld messages not recorded\n", opt.log.c_str(),
                 summary.log_failure.c_str(), static_cast<long long>(summary.log_lost));
    return fsw_app::kExitLogIncomplete;
  }
  return rc;
}
