#pragma once
// fsw_app's command line.
#include <cstdint>
#include <cstdio>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace fsw_app {

// The tasks a process runs (a bit each); by default all five, one thread each.
enum TaskBits : unsigned {
  kCameraTask = 1u << 0,
  kEstimatorTask = 1u << 1,
  kArmTask = 1u << 2,
  kManagerTask = 1u << 3,
  kLocalizerTask = 1u << 4,
  kAllTasks = kCameraTask | kEstimatorTask | kArmTask | kManagerTask | kLocalizerTask,
};

struct Options {
  std::string config = "fsw_app/config/fsw_app.json";
  std::string hal = "sim";
  std::string scenario;
  std::uint64_t seed = 1;
  std::string lcm_url;
  unsigned tasks = kAllTasks;
  bool publish_frames = false;
  std::string frames_from_log;
  bool perch = false;
  double timeout_s = 120.0;
  double duration_s = 0.0;
  std::string log;
  std::string summary_json;
  std::vector<std::pair<std::string, double>> faults;
  long budget_us = -1;
  std::string arm_port, gripper_port, camera_replay, handrail;
  bool quiet = false;
  // sim: the camera's path to the estimator, "raw" (raw phase frames through
  // the robot's ToF processing), "depth" (the depth renderer), "usb" (the
  // emulated Pico Flexx read by the USB driver) or "royale" (the same through
  // the royale API); real: "usb" or "royale"; and where
  // the simulated unit writes its calibration file for the processing to
  // read (empty: a file of this process's in the temporary directory).
  std::string camera = "raw";
  bool camera_given = false;
  std::string tof_calibration;
  // sim: the general-purpose localizer's bias (size; it turns slowly).
  double gp_bias_m = 0.03, gp_bias_deg = 1.0;

  bool runs(unsigned task) const { return (tasks & task) != 0; }
  // The simulated world (flyer, rendered camera, devices on ptys) is built
  // when a task here needs the simulated HAL's camera or devices.
  bool needs_sim_world() const { return hal == "sim" && (runs(kCameraTask) || runs(kArmTask)); }
  // What the summary names as the frames' path: "raw", "depth", "usb",
  // "royale", "replay", or "" when no camera task runs here.
  std::string camera_path() const {
    if (!runs(kCameraTask)) return "";
    if (hal == "sim") return camera;
    if (!camera_replay.empty()) return "replay";
    return camera == "royale" ? "royale" : "usb";
  }
  // The emulated camera (umockdev, in this process) is on the frames' path.
  bool emulated_usb_camera() const {
    return hal == "sim" && runs(kCameraTask) && (camera == "usb" || camera == "royale");
  }
};

void print_usage(std::FILE* out);

// Parses argv into *o. Returns an exit status when the program should stop
// now (0 after --help, 2 after a usage error, which it reports), nothing
// when it should run.
std::optional<int> parse_options(int argc, char** argv, Options* o);

// "camera,estimator" for the task bits.
std::string task_names(unsigned tasks);

}  // namespace fsw_app
