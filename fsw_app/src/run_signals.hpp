#pragma once
// SIGINT and SIGTERM, handled from the first line of main. Before the
// tasks start (options, configuration, scenario, devices) nothing has
// moved, so a signal ends the program at once (exit 128 + N); a
// configuration that takes long to read cannot hold it up. Once the tasks
// run, a signal asks the run loop for a safe stop (during a perch: the
// perch sequence's own ABORT, then the arm at rest); a second one ends the
// program at once.
namespace run_signals {

void install();
// From here on a first signal asks for a safe stop instead of ending.
void mark_tasks_running();
// The signal that asked for a stop; 0 while none came.
int stop_signal();

}  // namespace run_signals
