#pragma once
// What fsw_app reports at the end of a run: on the terminal, and as one JSON
// object (--summary-json) for the perch-runs script and the tests. Figures of a
// task that ran in another process are left out of the text and are -1 in
// the JSON.
#include <cstdint>
#include <cstdio>
#include <optional>
#include <string>

#include "app_options.hpp"
#include "dynamixel/bus.hpp"
#include "fsw_app/localization_score.hpp"
#include "fsw_app/localization_task.hpp"
#include "fsw_app/log_player.hpp"
#include "fsw_app/perch_manager.hpp"
#include "fsw_app/periodic_thread.hpp"
#include "fsw_app/royale_path_report.hpp"
#include "fsw_app/sighting_tally.hpp"
#include "fsw_app/usb_path_report.hpp"
#include "hrp/arm_state_t.hpp"
#include "hrp/estimator_health_t.hpp"
#include "hrp/input_health_t.hpp"
#include "pico_flexx/raw_depth_pipeline.hpp"

namespace fsw_app {

// Exit statuses besides 0 (perched, or a run that ended as asked), 1 (no
// perch, or a device that would not start) and 2 (bad options, files or
// configuration).
constexpr int kExitLogIncomplete = 3;  // the LCM log could not be written whole
// A perch stopped by a signal exits with 128 + the signal's number (130 for
// SIGINT, 143 for SIGTERM) after its safe stop; a run without --perch ends
// on a signal with 0, as it was asked to.

// A run ended by SIGINT or SIGTERM.
struct StopReport {
  bool stopped = false;
  int signal = 0;
  bool at_rest = false;  // the arm acknowledged the ABORT and came to rest
  double after_s = 0.0;  // from the signal to the end
};

struct RunSummary {
  bool perched = false;
  bool success = false;              // perched within 1 cm of the bar
  double time_to_perch_s = -1.0;     // from PERCH to PERCHED
  double grasp_error_m = -1.0;       // known only with the simulated world here
  double grasp_along_m = 0.0;        // along the bar from its middle (with grasp_error_m)
  hrp::arm_state_t arm{};            // the last ARM_STATE heard
  hrp::estimator_health_t health{};  // the last ESTIMATOR_HEALTH heard
  // Local tasks' own figures.
  std::optional<CycleStats> arm_loop;
  std::optional<dynamixel::BusCounters> servo_bus;
  std::optional<std::uint32_t> gripper_retries;
  double camera_longest_gap_ms = -1.0;
  // The camera as the perch manager saw it (a manager task here).
  std::optional<CameraWatch> camera_watch;
  // The frames' path ("raw", "depth", "usb", "royale", "replay"; "" without a camera
  // task here) and, on the raw and USB paths, the ToF processing's figures.
  std::string camera_path;
  std::optional<pico_flexx::PipelineCounts> tof;
  std::int64_t tof_median_us = -1;
  std::optional<UsbPathReport> usb;        // the USB path's driver (and emulated camera)
  std::optional<RoyalePathReport> royale;  // the camera through the royale API
  double estimator_longest_latency_ms = -1.0;
  // Frames the estimator could not place in the world: no robot pose at
  // their capture time (-1: no estimator task here).
  long long estimator_frames_without_pose = -1;
  // Why, by PoseAtStatus name: "TOO_OLD 4, GAP 1" and its JSON object.
  std::string without_pose_reasons, without_pose_reasons_json = "{}";
  std::optional<LogPlayerCounts> replay;
  std::int64_t log_messages = -1;
  std::int64_t log_depth_frames = -1;  // DEPTH_FRAME messages in the log
  std::int64_t log_lost = 0;           // heard after a failed write, not recorded
  std::string log_failure;             // empty: every write succeeded
  std::int64_t frames_published = -1;  // DEPTH_FRAME messages this process sent
  std::uint64_t receiver_faults = 0;   // exceptions the hub contained (never expected)
  hrp::input_health_t inputs{};        // this process's checked channels
  StopReport stop;
  std::optional<LocalizationScore> localization;  // the simulated world's scoring
  std::optional<LocalizerReport> localizer;       // a localization task here
  std::optional<SightingReport> sightings;        // HANDRAIL_ESTIMATE over the run
};

// "SIGINT", "SIGTERM".
const char* signal_name(int sig);

// The perch run's summary (result, times, frames, loops, links).
void print_perch_summary(const Options& opt, const RunSummary& s, std::FILE* out);
// A --frames-from-log run's summary (what was played, what the estimator did).
void print_replay_summary(const Options& opt, const RunSummary& s, std::FILE* out);
// False when the file cannot be written.
bool write_summary_json(const Options& opt, const RunSummary& s, const std::string& path);

}  // namespace fsw_app
