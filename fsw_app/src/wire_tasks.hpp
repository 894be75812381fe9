#pragma once
// This process's tasks (the --tasks subset), built on the camera, the
// arm's links and the hub, and wired to each other: the camera to the
// camera task, or to the frame publisher in front of it; the estimator to
// the camera task's ring. Nothing runs until start(), so that whoever
// watches the run can subscribe first.
#include <cstdint>
#include <memory>
#include <optional>

#include "app_options.hpp"
#include "arm_links.hpp"
#include "camera_source.hpp"
#include "fsw_app/app_config.hpp"
#include "fsw_app/arm_task.hpp"
#include "fsw_app/camera_task.hpp"
#include "fsw_app/estimator_task.hpp"
#include "fsw_app/frame_publisher.hpp"
#include "fsw_app/frame_ring.hpp"
#include "fsw_app/lcm_hub.hpp"
#include "fsw_app/localization_task.hpp"
#include "fsw_app/log_player.hpp"
#include "fsw_app/perch_manager.hpp"
#include "hal/clock.hpp"
#ifdef HRP_WITH_SIM
#include "hil_world.hpp"
#endif

namespace fsw_app {

class HilWorld;

// The tasks not run here stay nullptr. The members are destroyed in the
// reverse of their order: what holds a reference to a task goes first.
struct RunTasks {
  std::uint32_t max_w = 0, max_h = 0;  // the camera's largest frame; 0 with no camera here
  std::unique_ptr<FrameRing> ring;
  std::unique_ptr<CameraTask> camera_task;
  std::unique_ptr<FramePublisher> frame_publisher;
  std::unique_ptr<EstimatorTask> estimator_task;
  std::unique_ptr<ArmTask> arm_task;
  std::unique_ptr<PerchManager> manager;
  std::unique_ptr<LocalizationTask> localizer;
  std::unique_ptr<LogPlayer> player;
#ifdef HRP_WITH_SIM
  // The in-process cameras' stop for --fault camera-silent / camera-lost
  // (over USB the cable is pulled instead, for the driver to find again).
  std::unique_ptr<CameraCut> camera_cut;
#endif

  // Starts the tasks' threads; the hub's dispatcher is started first.
  void start();
};

// Builds *out: the camera initialised in the configured use case, the
// tasks of opt.tasks, the log player of --frames-from-log opened, and the
// camera capturing into its listener. `world` is the simulated world
// (nullptr without one). Returns an exit status after printing why, when
// the run cannot go on: 1 for a camera that will not start, 2 for a log
// that cannot be replayed.
std::optional<int> wire_tasks(const Options& opt, const AppConfig& cfg, LcmHub& hub,
                              const hal::Clock& clock, HilWorld* world, CameraSource& frames,
                              ArmLinks& links, RunTasks* out);

}  // namespace fsw_app
