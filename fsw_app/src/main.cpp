// fsw_app: the perching flight software. One process, a thread per task
// (camera, estimator, arm, perch manager), talking over LCM.
//
//   fsw_app --hal sim --scenario FILE [--perch] ...   hardware-in-loop on the simulated HAL
//   fsw_app --hal real --camera-replay DIR ...        robot ports, recorded frames
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
#include <cstdlib>
#include <cstring>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "arm_io/ax12_joints.hpp"
#include "arm_io/gripper_actuator.hpp"
#include "dynamixel/bus.hpp"
#include "fsw_app/app_config.hpp"
#include "fsw_app/arm_task.hpp"
#include "fsw_app/camera_task.hpp"
#include "fsw_app/estimator_task.hpp"
#include "fsw_app/lcm_hub.hpp"
#include "fsw_app/perch_manager.hpp"
#include "gripper/gripper_board.hpp"
#include "hal/linux_serial_port.hpp"
#include "hal/pcd_replay_camera.hpp"
#include "hal/realtime.hpp"
#include "hal/use_case.hpp"
#ifdef HRP_WITH_SIM
#include "hil_world.hpp"
#include "sim_hal/scenario.hpp"
#endif

namespace {

volatile sig_atomic_t g_stop = 0;
void on_signal(int) {
  g_stop = 1;
}

void usage(FILE* out) {
  std::fprintf(out,
               "usage: fsw_app [options]\n"
               "The handrail perching flight software: camera, estimator, arm and perch\n"
               "manager tasks on LCM.\n\n"
               "  --config FILE         configuration (default fsw_app/config/fsw_app.json)\n"
               "  --hal sim|real        simulated HAL (default) or the robot's devices\n"
               "  --scenario FILE       sim: the scene (sim_hal/scenarios/*.json)\n"
               "  --seed N              sim: start pose and disturbances (default 1)\n"
               "  --lcm-url URL         override the configuration's LCM URL\n"
               "  --perch               command PERCH, show progress, print a summary, exit\n"
               "  --timeout S           give up a --perch run after S seconds (default 120)\n"
               "  --duration S          without --perch: stop after S seconds (default: on ^C)\n"
               "  --log FILE            write every LCM message of the run to an LCM log\n"
               "  --summary-json FILE   write the summary as one JSON object\n"
               "  --fault NAME[@S]      sim: inject a fault S seconds (default 1) after the\n"
               "                        approach starts: servo-silent, gripper-overcurrent,\n"
               "                        occlude (1 s), corrupt-frames (5 frames)\n"
               "  --handrail iss|round  the handrail kind to look for (default from the config)\n"
               "  --budget-us N         the estimator's frame budget (default: the use case's\n"
               "                        frame period); a tiny one shows the over-budget path\n"
               "  --arm-port DEV        real: the Dynamixel bus (default from the config)\n"
               "  --gripper-port DEV    real: the gripper board (default from the config)\n"
               "  --camera-replay DIR   real: PCD frames played at the use case's rate in place\n"
               "                        of the camera\n"
               "  --quiet               no progress line\n"
               "  -h, --help            this text\n");
}

struct Options {
  std::string config = "fsw_app/config/fsw_app.json";
  std::string hal = "sim";
  std::string scenario;
  std::uint64_t seed = 1;
  std::string lcm_url;
  bool perch = false;
  double timeout_s = 120.0;
  double duration_s = 0.0;
  std::string log;
  std::string summary_json;
  std::vector<std::pair<std::string, double>> faults;
  long budget_us = -1;
  std::string arm_port, gripper_port, camera_replay, handrail;
  bool quiet = false;
};

int usage_error(const std::string& what) {
  std::fprintf(stderr, "fsw_app: %s (see fsw_app --help)\n", what.c_str());
  return 2;
}

std::optional<int> parse_args(int argc, char** argv, Options* o) {
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&](std::string* out) -> bool {
      if (i + 1 >= argc) return false;
      *out = argv[++i];
      return true;
    };
    std::string v;
    if (a == "-h" || a == "--help") {
      usage(stdout);
      return 0;
    } else if (a == "--perch") {
      o->perch = true;
    } else if (a == "--quiet") {
      o->quiet = true;
    } else if (a == "--config" || a == "--hal" || a == "--scenario" || a == "--seed" ||
               a == "--lcm-url" || a == "--timeout" || a == "--duration" || a == "--log" ||
               a == "--summary-json" || a == "--fault" || a == "--budget-us" || a == "--arm-port" ||
               a == "--gripper-port" || a == "--camera-replay" || a == "--handrail") {
      if (!value(&v)) return usage_error(a + " needs a value");
      char* end = nullptr;
      if (a == "--config") o->config = v;
      if (a == "--hal") o->hal = v;
      if (a == "--scenario") o->scenario = v;
      if (a == "--lcm-url") o->lcm_url = v;
      if (a == "--log") o->log = v;
      if (a == "--summary-json") o->summary_json = v;
      if (a == "--arm-port") o->arm_port = v;
      if (a == "--gripper-port") o->gripper_port = v;
      if (a == "--camera-replay") o->camera_replay = v;
      if (a == "--handrail") {
        if (v != "iss" && v != "round") return usage_error("--handrail is iss or round");
        o->handrail = v;
      }
      if (a == "--seed") {
        o->seed = std::strtoull(v.c_str(), &end, 10);
        if (*end) return usage_error("--seed wants a whole number, not \"" + v + "\"");
      }
      if (a == "--timeout" || a == "--duration") {
        const double s = std::strtod(v.c_str(), &end);
        if (*end || !(s > 0)) return usage_error(a + " wants seconds > 0, not \"" + v + "\"");
        (a == "--timeout" ? o->timeout_s : o->duration_s) = s;
      }
      if (a == "--budget-us") {
        o->budget_us = std::strtol(v.c_str(), &end, 10);
        if (*end || o->budget_us <= 0) return usage_error("--budget-us wants microseconds > 0");
      }
      if (a == "--fault") {
        const std::size_t at = v.find('@');
        const std::string name = v.substr(0, at);
        double t = 1.0;
        if (at != std::string::npos) {
          t = std::strtod(v.c_str() + at + 1, &end);
          if (*end || t < 0) return usage_error("--fault " + v + ": the time after @ is seconds");
        }
        if (name != "servo-silent" && name != "gripper-overcurrent" && name != "occlude" &&
            name != "corrupt-frames") {
          return usage_error("unknown fault \"" + name + "\"");
        }
        o->faults.push_back({name, t});
      }
    } else {
      return usage_error("unknown option \"" + a + "\"");
    }
  }
  if (o->hal != "sim" && o->hal != "real") return usage_error("--hal is sim or real");
  if (o->hal == "sim" && o->scenario.empty()) return usage_error("--hal sim needs --scenario FILE");
  if (o->hal == "real" && !o->faults.empty()) return usage_error("--fault needs --hal sim");
  return std::nullopt;
}

// Every message of the run into an LCM log (from the dispatcher thread).
struct RunLog {
  std::unique_ptr<lcm::LogFile> file;
  std::mutex mutex;
  std::int64_t events = 0;
  static void sink(void* user, const std::string& channel, const lcm::ReceiveBuffer& rbuf) {
    auto* self = static_cast<RunLog*>(user);
    std::lock_guard<std::mutex> lock(self->mutex);
    lcm::LogEvent e;
    e.eventnum = self->events++;
    e.timestamp = rbuf.recv_utime;
    e.channel = channel;
    e.datalen = static_cast<std::int32_t>(rbuf.data_size);
    e.data = rbuf.data;
    self->file->writeEvent(&e);
  }
};

const char* state_name(std::int8_t s) {
  return arm::to_string(static_cast<arm::PerchState>(s));
}

}  // namespace

int main(int argc, char** argv) {
  Options opt;
  if (auto rc = parse_args(argc, argv, &opt)) return *rc;
  signal(SIGINT, on_signal);
  signal(SIGTERM, on_signal);

  fsw_app::AppConfig cfg;
  std::string error;
  if (!fsw_app::load_app_config(opt.config, &cfg, &error)) {
    std::fprintf(stderr, "fsw_app: %s\n", error.c_str());
    return 2;
  }
  if (!opt.lcm_url.empty()) cfg.lcm_url = opt.lcm_url;
  if (!opt.handrail.empty()) {
    const float length = cfg.estimator.handrail.bar_length_m;
    cfg.estimator.handrail = opt.handrail == "iss" ? estimator::iss_handrail(length)
                                                   : estimator::paper_round_handrail(length);
  }
  if (!opt.arm_port.empty()) cfg.ports.servo_port = opt.arm_port;
  if (!opt.gripper_port.empty()) cfg.ports.gripper_port = opt.gripper_port;
  const hal::UseCase* use_case = hal::find_use_case(cfg.use_case);

  fsw_app::LcmHub hub(cfg.lcm_url);
  if (!hub.good()) {
    std::fprintf(stderr,
                 "fsw_app: LCM would not start on %s. For udpm on one host add the multicast "
                 "route: sudo ip link set lo multicast on; sudo ip route add 224.0.0.0/4 dev lo\n",
                 cfg.lcm_url.c_str());
    return 1;
  }
  RunLog log;
  if (!opt.log.empty()) {
    log.file = std::make_unique<lcm::LogFile>(opt.log, "w");
    if (!log.file->good()) {
      std::fprintf(stderr, "fsw_app: %s: cannot write the LCM log\n", opt.log.c_str());
      return 1;
    }
    hub.subscribe_all(&RunLog::sink, &log);
  }
  hal::MonotonicClock clock;

  // --- The HAL: camera and the arm's ports.
  std::unique_ptr<hal::DepthCamera> owned_camera;
  hal::DepthCamera* camera = nullptr;
  std::string servo_port = cfg.ports.servo_port, gripper_port = cfg.ports.gripper_port;
#ifdef HRP_WITH_SIM
  sim_hal::Scenario scenario;
  std::unique_ptr<fsw_app::HilWorld> world;
  if (opt.hal == "sim") {
    if (!sim_hal::load_scenario(opt.scenario, &scenario, &error)) {
      std::fprintf(stderr, "fsw_app: %s\n", error.c_str());
      return 2;
    }
    world = std::make_unique<fsw_app::HilWorld>(
        hub, scenario, cfg, fsw_app::hil_start_pose(scenario, cfg.T_body_cam, opt.seed), opt.seed,
        clock);
    if (!world->start(&error)) {
      std::fprintf(stderr, "fsw_app: simulated devices: %s\n", error.c_str());
      return 1;
    }
    camera = &world->camera();
    servo_port = world->servo_path();
    gripper_port = world->gripper_path();
  }
#else
  if (opt.hal == "sim") {
    std::fprintf(stderr,
                 "fsw_app: this build has no simulated HAL (a robot build); use --hal real\n");
    return 2;
  }
#endif
  if (opt.hal == "real") {
    if (opt.camera_replay.empty()) {
      std::fprintf(stderr,
                   "fsw_app: the Pico Flexx driver is not in this build yet; give recorded "
                   "frames with --camera-replay DIR\n");
      return 2;
    }
    auto replay = std::make_unique<hal::PcdReplayCamera>(opt.camera_replay, clock);
    if (!replay->load(&error)) {
      std::fprintf(stderr, "fsw_app: %s\n", error.c_str());
      return 2;
    }
    owned_camera = std::move(replay);
    camera = owned_camera.get();
  }

  // --- The arm's drivers on the ports.
  hal::LinuxSerialPort servo_serial, gripper_serial;
  if (servo_serial.open(servo_port, cfg.ports.servo_baud, &error) != hal::SerialStatus::kOk) {
    std::fprintf(stderr, "fsw_app: servo bus: %s\n", error.c_str());
    return 1;
  }
  if (gripper_serial.open(gripper_port, cfg.ports.gripper_baud, &error) != hal::SerialStatus::kOk) {
    std::fprintf(stderr, "fsw_app: gripper board: %s\n", error.c_str());
    return 1;
  }
  dynamixel::BusConfig bus_cfg;
  bus_cfg.return_delay_us = cfg.ports.servo_return_delay_us;
  // The simulated devices are threads of this process on a host that may
  // be shared (a virtual machine with steal time): their replies get a
  // wider margin than the wire needs, and the board a longer serial
  // timeout, so that a stalled host does not pass for a failed line.
  const bool sim = opt.hal == "sim";
  bus_cfg.margin_us = sim ? 100000 : cfg.ports.servo_margin_us;
  dynamixel::Bus bus(servo_serial, clock, bus_cfg);
  gripper::GripperBoard board(gripper_serial, clock, 2, sim ? 120000 : cfg.ports.gripper_margin_us);
  const std::uint32_t serial_timeout_ms =
      sim ? std::max<std::uint32_t>(cfg.ports.gripper_serial_timeout_ms, 2000)
          : cfg.ports.gripper_serial_timeout_ms;
  if (const gripper::Status s = board.set_timeout_ms(static_cast<int>(serial_timeout_ms));
      s != gripper::Status::kOk) {
    std::fprintf(stderr,
                 "fsw_app: gripper board on %s: could not set its serial timeout to %u ms (%s); "
                 "it keeps its own (500 ms after a reset)\n",
                 gripper_port.c_str(), serial_timeout_ms, gripper::to_string(s));
  }
  arm_io::Ax12Joints joints(bus, cfg.servos);
  arm_io::GripperActuator gripper(board);

  // --- The tasks.
  std::uint32_t max_w = 0, max_h = 0;
  if (camera->initialize() != hal::CameraStatus::kSuccess ||
      camera->set_use_case(cfg.use_case.c_str()) != hal::CameraStatus::kSuccess ||
      camera->max_frame_size(&max_w, &max_h) != hal::CameraStatus::kSuccess) {
    std::fprintf(stderr, "fsw_app: the camera would not take use case %s\n", cfg.use_case.c_str());
    return 1;
  }
  fsw_app::FrameRing ring(3, max_w, max_h);
  fsw_app::CameraTask camera_task(ring, max_w, max_h);
  fsw_app::EstimatorTaskConfig est_cfg;
  est_cfg.detector = cfg.estimator;
  est_cfg.detector.budget_us = opt.budget_us > 0 ? opt.budget_us : hal::frame_period_us(*use_case);
  est_cfg.T_body_cam = cfg.T_body_cam;
  est_cfg.arm = cfg.perch.geometry;
  est_cfg.max_width = max_w;
  est_cfg.max_height = max_h;
  fsw_app::EstimatorTask estimator_task(hub, camera_task, ring, est_cfg, clock);
  fsw_app::ArmTask arm_task(hub, joints, gripper, cfg.perch, clock, cfg.arm_rate_hz,
                            cfg.arm_rt_priority);
  const Eigen::Vector3d p_body_grasp =
      arm::forward_kinematics(cfg.perch.geometry, cfg.perch.geometry.grip).translation();
  fsw_app::PerchManager manager(hub, cfg.approach, p_body_grasp, clock, cfg.manager_rate_hz);
  if (camera->register_data_listener(&camera_task) != hal::CameraStatus::kSuccess ||
      camera->start_capture() != hal::CameraStatus::kSuccess) {
    std::fprintf(stderr, "fsw_app: the camera would not start capturing\n");
    return 1;
  }
  hub.start();
  estimator_task.start();
  arm_task.start();
  manager.start();

  // --- The run.
  fsw_app::Mailbox<hrp::arm_state_t> arm_box;
  fsw_app::Mailbox<hrp::estimator_health_t> health_box;
  fsw_app::Mailbox<hrp::approach_status_t> approach_box;
  hub.subscribe(fsw_app::channel::kArmState, &arm_box);
  hub.subscribe(fsw_app::channel::kEstimatorHealth, &health_box);
  hub.subscribe(fsw_app::channel::kApproachStatus, &approach_box);
  fsw_app::Publisher<hrp::perch_command_t> command_pub(hub, fsw_app::channel::kPerchCommand);
  const bool tty = isatty(STDERR_FILENO) && !opt.quiet;
  const auto t0 = std::chrono::steady_clock::now();
  auto seconds = [&] {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  };
  hrp::arm_state_t arm{};
  hrp::approach_status_t approach{};
  bool commanded = false, approach_started = false, done = false, perched = false;
  double perch_cmd_s = 0.0, perched_s = 0.0, last_print = -10.0;
#ifdef HRP_WITH_SIM
  double approach_s = 0.0;
  std::size_t next_fault = 0;
#endif
  int rc = 0;
  bool realtime_reported = false;
  while (!g_stop && !done) {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    const double t = seconds();
    if (!realtime_reported && cfg.arm_rt_priority > 0 && arm_task.cycle_stats().cycles > 0) {
      realtime_reported = true;
      const hal::RealtimeStatus rt = arm_task.cycle_stats().realtime;
      if (rt != hal::RealtimeStatus::kGranted) {
        std::fprintf(stderr,
                     "fsw_app: arm loop: SCHED_FIFO priority %d %s; it runs under the normal "
                     "scheduler (run as root, grant CAP_SYS_NICE, or set an rtprio limit)\n",
                     cfg.arm_rt_priority, hal::to_string(rt));
      }
    }
    const bool have_arm = arm_box.read(&arm) != 0;
    approach_box.read(&approach);
    if (opt.perch && !commanded && have_arm && arm.state == hrp::arm_state_t::STOWED) {
      hrp::perch_command_t c{};
      c.utime = clock.now_us();
      c.sequence = 1;
      c.command = hrp::perch_command_t::PERCH;
      command_pub.publish(c);
      commanded = true;
      perch_cmd_s = t;
    }
    if (have_arm && arm.state == hrp::arm_state_t::GRIPPER_OPEN && !approach_started) {
      approach_started = true;
#ifdef HRP_WITH_SIM
      approach_s = t;
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
      } else if (f == "corrupt-frames") {
        world->corrupt_next_frames(5);
      }
    }
#endif
    if (opt.perch && commanded) {
      if (arm.state == hrp::arm_state_t::PERCHED && perched_s == 0.0) perched_s = t;
      if (perched_s > 0.0 && t - perched_s > 1.0) {
        perched = true;
        done = true;
      }
      if (arm.state == hrp::arm_state_t::FAULT) done = true;
      if (t - perch_cmd_s > opt.timeout_s) done = true;
    }
    if (!opt.perch && opt.duration_s > 0 && t > opt.duration_s) done = true;
    if (!opt.quiet && (tty || t - last_print >= 2.0)) {
      last_print = t;
      std::fprintf(stderr, "%s%6.1f s  arm %-12s  target %s  error %6.3f m %5.1f deg%s",
                   tty ? "\r" : "", t, have_arm ? state_name(arm.state) : "-",
                   approach.utime ? "seen" : "none", approach.position_error_m,
                   approach.angle_error_rad * 180.0 / M_PI, tty ? "   " : "\n");
    }
  }
  if (tty) std::fprintf(stderr, "\n");
  const fsw_app::CycleStats arm_stats = arm_task.cycle_stats();
  const fsw_app::EstimatorCounters est_stats = estimator_task.counters();
  const double camera_gap_ms = 1e-3 * static_cast<double>(camera_task.longest_gap_us());
  const double latency_ms = 1e-3 * static_cast<double>(est_stats.longest_latency_us);
  manager.stop();
  arm_task.stop();
  (void)camera->stop_capture();
  estimator_task.stop();
  estimator_task.publish_health();
  std::this_thread::sleep_for(std::chrono::milliseconds(100));
  hub.stop();

  hrp::estimator_health_t health{};
  health_box.read(&health);
  arm_box.read(&arm);
  double grasp_error = -1.0;
#ifdef HRP_WITH_SIM
  if (world) {
    grasp_error = world->stats().grasp_error_m;
    world->stop();
  }
#endif
  const bool success = perched && grasp_error >= 0.0 && grasp_error <= 0.01;
  if (opt.perch) {
    std::printf("summary\n");
    std::printf("  result              %s\n",
                perched ? "PERCHED" : (arm.state == hrp::arm_state_t::FAULT ? "FAULT" : "TIMEOUT"));
    std::printf("  arm state           %s%s%s\n", arm.state_name.c_str(),
                arm.fault_text.empty() ? "" : ": ", arm.fault_text.c_str());
    if (perched) std::printf("  time to perch       %.1f s after PERCH\n", perched_s - perch_cmd_s);
    if (grasp_error >= 0.0) {
      std::printf("  gripper to bar      %.1f mm when the grip closed\n", grasp_error * 1000.0);
    }
    std::printf("  frames              %lld received, %lld processed, %lld dropped, %lld corrupt\n",
                static_cast<long long>(health.frames_received),
                static_cast<long long>(health.frames_processed),
                static_cast<long long>(health.frames_dropped),
                static_cast<long long>(health.frames_corrupt));
    std::printf("  deadline misses     %lld (budget %d us; processing median %d us, max %d us)\n",
                static_cast<long long>(health.deadline_misses), health.budget_us,
                health.processing_median_us, health.processing_max_us);
    std::printf(
        "  arm loop            %lld cycles, %lld overruns, longest gap %.0f ms, "
        "longest cycle %.0f ms, real-time %s\n",
        static_cast<long long>(arm_stats.cycles), static_cast<long long>(arm_stats.overruns),
        1e-3 * arm_stats.longest_gap_us, 1e-3 * arm_stats.longest_cycle_us,
        hal::to_string(arm_stats.realtime));
    std::printf(
        "  frame pipeline      longest gap between frames %.0f ms, longest capture to "
        "estimate %.0f ms\n",
        camera_gap_ms, latency_ms);
    const dynamixel::BusCounters& bc = bus.counters();
    std::printf(
        "  servo bus           %u transactions, %u retries, %u timeouts, %u bad checksums\n",
        bc.transactions, bc.retries, bc.timeouts, bc.bad_checksums);
    std::printf("  gripper board       %u retries\n", board.retries_used());
    if (!opt.log.empty())
      std::printf("  LCM log             %s (%lld messages)\n", opt.log.c_str(),
                  static_cast<long long>(log.events));
    rc = success ? 0 : 1;
  }
  if (!opt.summary_json.empty()) {
    FILE* f = std::fopen(opt.summary_json.c_str(), "w");
    if (!f) {
      std::fprintf(stderr, "fsw_app: %s: cannot write the summary\n", opt.summary_json.c_str());
      return 1;
    }
    std::fprintf(f,
                 "{\"seed\": %llu, \"scenario\": \"%s\", \"perched\": %s, \"success\": %s, "
                 "\"arm_state\": \"%s\", \"fault\": \"%s\", \"fault_text\": \"%s\", "
                 "\"time_to_perch_s\": %.2f, \"grasp_error_m\": %.4f, \"frames_received\": %lld, "
                 "\"frames_processed\": %lld, \"frames_dropped\": %lld, \"frames_corrupt\": %lld, "
                 "\"deadline_misses\": %lld, \"processing_median_us\": %d, \"arm_cycles\": %lld, "
                 "\"arm_overruns\": %lld, \"arm_longest_gap_ms\": %.1f, \"arm_realtime\": \"%s\", "
                 "\"camera_longest_gap_ms\": %.1f, \"estimator_longest_latency_ms\": %.1f}\n",
                 static_cast<unsigned long long>(opt.seed), opt.scenario.c_str(),
                 perched ? "true" : "false", success ? "true" : "false", arm.state_name.c_str(),
                 arm.fault_name.c_str(), arm.fault_text.c_str(),
                 perched ? perched_s - perch_cmd_s : -1.0, grasp_error,
                 static_cast<long long>(health.frames_received),
                 static_cast<long long>(health.frames_processed),
                 static_cast<long long>(health.frames_dropped),
                 static_cast<long long>(health.frames_corrupt),
                 static_cast<long long>(health.deadline_misses), health.processing_median_us,
                 static_cast<long long>(arm_stats.cycles),
                 static_cast<long long>(arm_stats.overruns), 1e-3 * arm_stats.longest_gap_us,
                 hal::to_string(arm_stats.realtime), camera_gap_ms, latency_ms);
    std::fclose(f);
  }
  return rc;
}
