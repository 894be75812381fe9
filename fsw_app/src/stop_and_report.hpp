#pragma once
// The end of a run: the tasks stopped in an order that keeps their last
// figures, the summary gathered from them, the hub, the log and the
// simulated world, then printed and written, and the exit status chosen.
#include "app_options.hpp"
#include "arm_links.hpp"
#include "camera_source.hpp"
#include "fsw_app/lcm_hub.hpp"
#include "hal/clock.hpp"
#include "run_log.hpp"
#include "run_until_done.hpp"
#include "run_watch.hpp"
#include "wire_tasks.hpp"

namespace fsw_app {

class HilWorld;

// Stops everything this process runs (the hub too), closes the log,
// prints the perch or replay summary, writes --summary-json, and returns
// the exit status: for a perch 0 within 1 cm of the bar, 1 otherwise,
// 128 + N after a safe stop on signal N; 1 when the summary cannot be
// written, kExitLogIncomplete when the log is not whole. `world` is the
// simulated world, or nullptr.
int stop_and_report(const Options& opt, LcmHub& hub, const hal::Clock& clock, RunWatch& watch,
                    RunTasks& tasks, ArmLinks& links, CameraSource& frames, HilWorld* world,
                    RunLog& log, const RunOutcome& outcome);

}  // namespace fsw_app
