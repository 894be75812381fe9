#pragma once
// The run, once the tasks are running: the main thread wakes every 50 ms
// to publish the input counts, send PERCH, inject the timed faults, draw
// progress, and decide when the run is over (perched, a fault at rest, a
// timeout, the end of a replay or of --duration, a signal's safe stop).
#include "app_options.hpp"
#include "camera_source.hpp"
#include "fsw_app/app_config.hpp"
#include "hal/clock.hpp"
#include "run_summary.hpp"
#include "run_watch.hpp"
#include "wire_tasks.hpp"

namespace fsw_app {

class HilWorld;

// How the run ended, for the summary.
struct RunOutcome {
  bool perched = false;      // PERCHED and held for 1 s
  double perch_cmd_s = 0.0;  // PERCH sent, seconds from the run's start
  double perched_s = 0.0;    // PERCHED first reported (0: never)
  StopReport stop;           // the safe stop a signal asked for, if one did
};

// Runs until the run is over and returns how it ended. `world` is the
// simulated world (nullptr without one), where the faults go.
RunOutcome run_until_done(const Options& opt, const AppConfig& cfg, const hal::Clock& clock,
                          RunWatch& watch, RunTasks& tasks, CameraSource& frames, HilWorld* world);

}  // namespace fsw_app
