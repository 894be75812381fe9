#pragma once
// The run's configuration: the file, then what the command line changes in
// it. Kept apart from the task wiring so that everything a run is told is
// settled, and every mistake in it reported, before anything starts.
#include <optional>

#include "app_options.hpp"
#include "fsw_app/app_config.hpp"

namespace fsw_app {

// Loads opt.config into *cfg and applies --lcm-url, --handrail,
// --arm-port and --gripper-port; asks for a frame-sized receive buffer
// when this process hears depth frames over udpm. Returns an exit status
// (2) after printing why, when the run cannot go on.
std::optional<int> load_run_config(const Options& opt, AppConfig* cfg);

}  // namespace fsw_app
