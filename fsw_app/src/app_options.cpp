#include "app_options.hpp"

#include <cstdlib>
#include <cstring>

namespace fsw_app {

namespace {

struct TaskName {
  const char* name;
  unsigned bit;
};
constexpr TaskName kTaskNames[] = {{"camera", kCameraTask},
                                   {"estimator", kEstimatorTask},
                                   {"arm", kArmTask},
                                   {"manager", kManagerTask},
                                   {"localizer", kLocalizerTask}};

int usage_error(const std::string& what) {
  std::fprintf(stderr, "fsw_app: %s (see fsw_app --help)\n", what.c_str());
  return 2;
}

// "camera,estimator" or "all" into bits; false on an unknown name.
bool parse_tasks(const std::string& list, unsigned* tasks, std::string* bad) {
  *tasks = 0;
  std::size_t start = 0;
  while (start <= list.size()) {
    const std::size_t comma = list.find(',', start);
    const std::string name =
        list.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
    unsigned bit = 0;
    if (name == "all") bit = kAllTasks;
    for (const TaskName& t : kTaskNames) {
      if (name == t.name) bit = t.bit;
    }
    if (bit == 0) {
      *bad = name;
      return false;
    }
    *tasks |= bit;
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return true;
}

// After parsing: the combinations that cannot run, named.
std::optional<int> check_combination(Options* o, bool tasks_given) {
  if (o->hal != "sim" && o->hal != "real") return usage_error("--hal is sim or real");
  if (!o->frames_from_log.empty()) {
    if (!tasks_given) o->tasks = kEstimatorTask;
    if (!o->runs(kEstimatorTask) || o->runs(kCameraTask)) {
      return usage_error(
          "--frames-from-log feeds the estimator in place of the camera: use it with --tasks "
          "estimator (and arm or manager if wanted), not with the camera task");
    }
  }
  if (o->needs_sim_world() && o->scenario.empty()) {
    return usage_error("--hal sim needs --scenario FILE for the " +
                       task_names(o->tasks & (kCameraTask | kArmTask)) + " task");
  }
  if (!o->faults.empty() && !o->needs_sim_world()) {
    return usage_error("--fault needs --hal sim with the camera or arm task in this process");
  }
  for (const auto& fault : o->faults) {
    const bool camera_fault = fault.first == "camera-silent" || fault.first == "camera-lost";
    if (camera_fault && !o->runs(kCameraTask)) {
      return usage_error("--fault " + fault.first +
                         " acts on the camera: it needs the camera task");
    }
  }
  if (o->camera != "raw" && o->camera != "depth" && o->camera != "usb" && o->camera != "royale") {
    return usage_error("--camera is raw, depth, usb or royale");
  }
  if (o->hal == "real" && o->camera_given && o->camera != "usb" && o->camera != "royale") {
    return usage_error(
        "--camera " + o->camera +
        " is a simulated camera's path (--hal sim); with --hal real the camera task reads the "
        "Pico Flexx with the project's USB driver (--camera usb, the default) or through the "
        "royale API (--camera royale), or plays --camera-replay");
  }
  if (o->hal == "real" && !o->tof_calibration.empty()) {
    return usage_error(
        "--tof-calibration is the simulated camera's (--hal sim --camera raw): a real Pico "
        "Flexx carries its own calibration");
  }
  if (o->hal == "real" && o->camera_given && !o->camera_replay.empty()) {
    return usage_error(
        "--camera-replay plays recorded frames in place of the camera: drop --camera");
  }
  if (!o->tof_calibration.empty() && o->camera != "raw") {
    return usage_error(
        "--tof-calibration is the raw path's calibration file (--camera raw): the depth "
        "renderer needs none, and over USB (--camera usb) it is read from the camera");
  }
  for (const auto& fault : o->faults) {
    const bool usb_fault = fault.first == "usb-unplug" || fault.first == "usb-stall";
    if (usb_fault && !o->emulated_usb_camera()) {
      return usage_error("--fault " + fault.first +
                         " acts on the emulated camera: it needs --hal sim --camera usb (or "
                         "royale) with the camera task");
    }
  }
  return std::nullopt;
}

}  // namespace

std::string task_names(unsigned tasks) {
  std::string out;
  for (const TaskName& t : kTaskNames) {
    if ((tasks & t.bit) == 0) continue;
    if (!out.empty()) out += ",";
    out += t.name;
  }
  return out;
}

void print_usage(std::FILE* out) {
  std::fprintf(out,
               "usage: fsw_app [options]\n"
               "The handrail perching flight software: camera, estimator, arm, perch\n"
               "manager and localizer tasks on LCM.\n\n"
               "  --config FILE         configuration (default fsw_app/config/fsw_app.json)\n"
               "  --hal sim|real        simulated HAL (default) or the robot's devices\n"
               "  --scenario FILE       sim: the scene (sim_hal/scenarios/*.json)\n"
               "  --seed N              sim: start pose and disturbances (default 1)\n"
               "  --tasks LIST          the tasks this process runs, comma separated, from\n"
               "                        camera, estimator, arm, manager, localizer (default\n"
               "                        all). An\n"
               "                        estimator without the camera reads DEPTH_FRAME; a\n"
               "                        camera without the estimator publishes it\n"
               "  --publish-frames      put every depth frame on DEPTH_FRAME (0.73 MB each),\n"
               "                        so that --log records a run that can be replayed\n"
               "  --frames-from-log LOG replay LOG's DEPTH_FRAME and ROBOT_POSE messages into\n"
               "                        the estimator at their recorded pace, then stop\n"
               "                        (implies --tasks estimator unless --tasks is given)\n"
               "  --lcm-url URL         override the configuration's LCM URL\n"
               "  --perch               command PERCH, show progress, print a summary, exit\n"
               "  --timeout S           give up a --perch run after S seconds (default 120)\n"
               "  --duration S          without --perch: stop after S seconds (default: on ^C)\n"
               "  --log FILE            write every LCM message of the run to an LCM log\n"
               "  --summary-json FILE   write the summary as one JSON object\n"
               "  --fault NAME[@S]      sim: inject a fault S seconds (default 1) after the\n"
               "                        approach starts: servo-silent, gripper-overcurrent,\n"
               "                        occlude (1 s), corrupt-frames (5 frames), imu-silent\n"
               "                        (0.5 s), gp-jump (the GP pose 20 cm off from then on),\n"
               "                        handrail-lost (the camera sees nothing from then on),\n"
               "                        imu-lost (no IMU sample from then on, so no robot pose),\n"
               "                        camera-silent (no frame for 2 s), camera-lost (no frame\n"
               "                        from then on; over USB the cable is pulled);\n"
               "                        with --camera usb or royale also usb-unplug (the\n"
               "                        cable out for 0.5 s) and usb-stall (the stream\n"
               "                        endpoint halted)\n"
               "  --camera raw|depth|usb|royale\n"
               "                        sim: the frames' path (default raw): the raw renderer's\n"
               "                        phase frames through the robot's ToF processing; the\n"
               "                        depth renderer's frames; usb: the raw frames from an\n"
               "                        emulated Pico Flexx (umockdev) read by the robot's USB\n"
               "                        driver through libusb, then the ToF processing; royale:\n"
               "                        the same camera through the royale API.\n"
               "                        real: usb (default), the project's driver, or royale,\n"
               "                        the royale API (the vendor's SDK in a build configured\n"
               "                        with HRP_ROYALE_SDK_DIR, else the project's)\n"
               "  --tof-calibration FILE sim, raw path: where the simulated unit writes its\n"
               "                        calibration file, which the processing then reads\n"
               "                        (default: a temporary file, removed once read)\n"
               "  --gp-error M,DEG      sim: the general-purpose localizer's bias, metres and\n"
               "                        degrees (default 0.03,1); its direction turns slowly\n"
               "  --handrail iss|round  the handrail kind to look for (default from the config)\n"
               "  --budget-us N         the estimator's frame budget (default: the use case's\n"
               "                        frame period); a tiny one shows the over-budget path\n"
               "  --arm-port DEV        real: the Dynamixel bus (default from the config)\n"
               "  --gripper-port DEV    real: the gripper board (default from the config)\n"
               "  --camera-replay DIR   real: PCD frames played at the use case's rate in place\n"
               "                        of the camera (without it: the Pico Flexx over USB,\n"
               "                        the first one found or the config's camera.serial)\n"
               "  --quiet               no progress line\n"
               "  -h, --help            this text\n");
}

std::optional<int> parse_options(int argc, char** argv, Options* o) {
  bool tasks_given = false;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "-h" || a == "--help") {
      print_usage(stdout);
      return 0;
    }
    if (a == "--perch") {
      o->perch = true;
      continue;
    }
    if (a == "--quiet") {
      o->quiet = true;
      continue;
    }
    if (a == "--publish-frames") {
      o->publish_frames = true;
      continue;
    }
    static const char* const kWithValue[] = {
        "--config",          "--hal",           "--scenario",  "--seed",
        "--lcm-url",         "--timeout",       "--duration",  "--log",
        "--summary-json",    "--fault",         "--budget-us", "--arm-port",
        "--gripper-port",    "--camera-replay", "--handrail",  "--tasks",
        "--frames-from-log", "--gp-error",      "--camera",    "--tof-calibration"};
    bool known = false;
    for (const char* k : kWithValue) known = known || a == k;
    if (!known) return usage_error("unknown option \"" + a + "\"");
    if (i + 1 >= argc) return usage_error(a + " needs a value");
    const std::string v = argv[++i];
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
    if (a == "--frames-from-log") o->frames_from_log = v;
    if (a == "--tof-calibration") o->tof_calibration = v;
    if (a == "--camera") {
      o->camera = v;
      o->camera_given = true;
    }
    if (a == "--tasks") {
      std::string bad;
      if (!parse_tasks(v, &o->tasks, &bad)) {
        return usage_error("--tasks: unknown task \"" + bad +
                           "\" (camera, estimator, arm, manager, localizer or all)");
      }
      tasks_given = true;
    }
    if (a == "--handrail") {
      if (v != "iss" && v != "round") return usage_error("--handrail is iss or round");
      o->handrail = v;
    }
    if (a == "--seed") {
      o->seed = std::strtoull(v.c_str(), &end, 10);
      if (*end || v.empty()) return usage_error("--seed wants a whole number, not \"" + v + "\"");
    }
    if (a == "--timeout" || a == "--duration") {
      const double s = std::strtod(v.c_str(), &end);
      if (*end || !(s > 0)) return usage_error(a + " wants seconds > 0, not \"" + v + "\"");
      (a == "--timeout" ? o->timeout_s : o->duration_s) = s;
    }
    if (a == "--gp-error") {
      const double m = std::strtod(v.c_str(), &end);
      const double deg = *end == ',' ? std::strtod(end + 1, &end) : -1.0;
      if (*end || !(m >= 0.0 && m <= 1.0) || !(deg >= 0.0 && deg <= 30.0)) {
        return usage_error("--gp-error wants METRES,DEGREES (0..1, 0..30), not \"" + v + "\"");
      }
      o->gp_bias_m = m;
      o->gp_bias_deg = deg;
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
          name != "corrupt-frames" && name != "imu-silent" && name != "gp-jump" &&
          name != "handrail-lost" && name != "imu-lost" && name != "usb-unplug" &&
          name != "usb-stall" && name != "camera-silent" && name != "camera-lost") {
        return usage_error("unknown fault \"" + name + "\"");
      }
      o->faults.push_back({name, t});
    }
  }
  return check_combination(o, tasks_given);
}

}  // namespace fsw_app
