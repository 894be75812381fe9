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
//
// main() only puts the steps in order; each is a file of its own. The
// objects below are destroyed in the reverse of their order on every
// return: the run's watchers, then the tasks, before the camera and links
// they use; those before the simulated world; the hub after all of them.
#include <cstdio>
#include <memory>
#include <string>

#include "app_options.hpp"
#include "arm_links.hpp"
#include "camera_source.hpp"
#include "fsw_app/app_config.hpp"
#include "fsw_app/lcm_hub.hpp"
#include "hal/clock.hpp"
#include "load_run_config.hpp"
#include "open_lcm_hub.hpp"
#include "run_log.hpp"
#include "run_signals.hpp"
#include "run_until_done.hpp"
#include "run_watch.hpp"
#include "start_sim_world.hpp"
#include "stop_and_report.hpp"
#include "wire_tasks.hpp"
#ifdef HRP_WITH_SIM
#include "sim_hal/umockdev_preload.hpp"
#endif

int main(int argc, char** argv) {
  run_signals::install();
  fsw_app::Options opt;
  if (auto rc = fsw_app::parse_options(argc, argv, &opt)) return *rc;
#ifdef HRP_WITH_SIM
  // The emulated USB camera lives in this process and needs umockdev's
  // preload library under it: the program starts itself again with it.
  if (opt.emulated_usb_camera()) {
    sim_hal::umockdev_preload::ensure(argv);
  }
#endif

  fsw_app::AppConfig cfg;
  if (auto rc = fsw_app::load_run_config(opt, &cfg)) return *rc;
  std::unique_ptr<fsw_app::LcmHub> hub_owner;
  if (auto rc = fsw_app::open_lcm_hub(opt, &cfg, &hub_owner)) return *rc;
  fsw_app::LcmHub& hub = *hub_owner;
  fsw_app::RunLog log;
  if (!opt.log.empty()) {
    std::string error;
    if (!log.open(opt.log, &error)) {
      std::fprintf(stderr, "fsw_app: %s\n", error.c_str());
      return 1;
    }
    hub.subscribe_all(&fsw_app::RunLog::sink, &log);
  }
  hal::MonotonicClock clock;

  // The devices: the simulated world when a task here needs it, where
  // frames come from (camera_source.hpp), the arm's drivers on the ports.
  fsw_app::SimWorld sim;
  if (auto rc = fsw_app::start_sim_world(opt, cfg, hub, clock, &sim)) return *rc;
  fsw_app::CameraSource frames;
  if (auto rc =
          fsw_app::open_camera_source(opt, cfg, hub, sim.hil(), sim.scene(), clock, &frames)) {
    return *rc;
  }
  fsw_app::ArmLinks links;
  if (opt.runs(fsw_app::kArmTask) && !fsw_app::open_arm_links(cfg, sim.servo_port, sim.gripper_port,
                                                              opt.hal == "sim", clock, &links)) {
    return 1;
  }

  // The tasks, then what the run watches; nothing runs before both exist.
  fsw_app::RunTasks tasks;
  if (auto rc = fsw_app::wire_tasks(opt, cfg, hub, clock, sim.hil(), frames, links, &tasks)) {
    return *rc;
  }
  fsw_app::RunWatch watch(hub, cfg, opt.tasks);
  run_signals::mark_tasks_running();
  hub.start();
  tasks.start();

  const fsw_app::RunOutcome outcome =
      fsw_app::run_until_done(opt, cfg, clock, watch, tasks, frames, sim.hil());
  return fsw_app::stop_and_report(opt, hub, clock, watch, tasks, links, frames, sim.hil(), log,
                                  outcome);
}
