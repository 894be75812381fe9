#include "wire_tasks.hpp"

#include <cstdio>
#include <string>

#include "arm/arm_model.hpp"
#include "hal/use_case.hpp"

namespace fsw_app {

namespace {

// The camera initialised, in the configured use case and exposure, with
// the ring its largest frames fit and the camera task on it. Before the
// estimator, which is sized by the same frames.
std::optional<int> open_camera(const Options& opt, const AppConfig& cfg, LcmHub& hub,
                               const hal::Clock& clock, CameraSource& frames, RunTasks* out) {
  hal::DepthCamera* camera = frames.camera();
  const hal::CameraStatus init = camera->initialize();
  if (init != hal::CameraStatus::kSuccess) {
    const std::string detail = frames.failure_detail();
    std::fprintf(stderr, "fsw_app: the camera would not initialize: %s%s%s\n", hal::to_string(init),
                 detail.empty() ? "" : ": ", detail.c_str());
    return 1;
  }
  if (camera->set_use_case(cfg.use_case.c_str()) != hal::CameraStatus::kSuccess ||
      camera->max_frame_size(&out->max_w, &out->max_h) != hal::CameraStatus::kSuccess) {
    std::fprintf(stderr, "fsw_app: the camera would not take use case %s\n", cfg.use_case.c_str());
    return 1;
  }
  const hal::CameraStatus configured = frames.configure_after_use_case();
  if (configured != hal::CameraStatus::kSuccess) {
    std::fprintf(stderr, "fsw_app: the camera would not take automatic exposure: %s\n",
                 hal::to_string(configured));
    return 1;
  }
  out->ring = std::make_unique<FrameRing>(3, out->max_w, out->max_h);
  out->camera_task = std::make_unique<CameraTask>(*out->ring, out->max_w, out->max_h);
  if (frames.lcm_camera() == nullptr && (opt.publish_frames || !opt.runs(kEstimatorTask))) {
    out->frame_publisher =
        std::make_unique<FramePublisher>(hub, clock, out->max_w, out->max_h, *out->camera_task);
  }
  return std::nullopt;
}

// The camera's frames into their listener, capturing. Last, once every
// task that takes frames exists.
std::optional<int> start_capture(const hal::Clock& clock, HilWorld* world, CameraSource& frames,
                                 RunTasks* out) {
  hal::DepthDataListener* listener = out->camera_task.get();
  if (out->frame_publisher) listener = out->frame_publisher.get();
#ifdef HRP_WITH_SIM
  if (world && !frames.hil_usb()) {
    out->camera_cut = std::make_unique<CameraCut>(clock, *listener);
    listener = out->camera_cut.get();
  }
#else
  (void)clock;
  (void)world;
#endif
  hal::DepthCamera* camera = frames.camera();
  if (camera->register_data_listener(listener) != hal::CameraStatus::kSuccess ||
      camera->start_capture() != hal::CameraStatus::kSuccess) {
    std::fprintf(stderr, "fsw_app: the camera would not start capturing\n");
    return 1;
  }
  return std::nullopt;
}

}  // namespace

void RunTasks::start() {
  if (localizer) localizer->start();
  if (estimator_task) estimator_task->start();
  if (arm_task) arm_task->start();
  if (manager) manager->start();
  if (player) player->start();
}

std::optional<int> wire_tasks(const Options& opt, const AppConfig& cfg, LcmHub& hub,
                              const hal::Clock& clock, HilWorld* world, CameraSource& frames,
                              ArmLinks& links, RunTasks* out) {
  if (frames.camera()) {
    if (auto rc = open_camera(opt, cfg, hub, clock, frames, out)) return rc;
  }
  if (opt.runs(kEstimatorTask)) {
    const hal::UseCase* use_case = hal::find_use_case(cfg.use_case);
    EstimatorTaskConfig est_cfg;
    est_cfg.detector = cfg.estimator;
    est_cfg.detector.budget_us =
        opt.budget_us > 0 ? opt.budget_us : hal::frame_period_us(*use_case);
    est_cfg.T_body_cam = cfg.T_body_cam;
    est_cfg.arm = cfg.perch.geometry;
    est_cfg.max_width = out->max_w;
    est_cfg.max_height = out->max_h;
    out->estimator_task =
        std::make_unique<EstimatorTask>(hub, *out->camera_task, *out->ring, est_cfg, clock);
  }
  if (opt.runs(kArmTask)) {
    out->arm_task = std::make_unique<ArmTask>(hub, *links.joints, *links.gripper, cfg.perch, clock,
                                              cfg.arm_rate_hz, cfg.arm_rt_priority);
  }
  if (opt.runs(kManagerTask)) {
    const Eigen::Vector3d p_body_grasp =
        arm::forward_kinematics(cfg.perch.geometry, cfg.perch.geometry.grip).translation();
    out->manager =
        std::make_unique<PerchManager>(hub, cfg.approach, p_body_grasp, clock, cfg.manager_rate_hz);
  }
  if (opt.runs(kLocalizerTask)) {
    out->localizer = std::make_unique<LocalizationTask>(hub, localization_task_config(cfg), clock);
  }
  if (!opt.frames_from_log.empty()) {
    out->player =
        std::make_unique<LogPlayer>(hub, opt.frames_from_log, clock, out->max_w, out->max_h);
    std::string error;
    if (!out->player->open(&error)) {
      std::fprintf(stderr, "fsw_app: --frames-from-log %s\n", error.c_str());
      return 2;
    }
  }
  if (frames.camera()) return start_capture(clock, world, frames, out);
  return std::nullopt;
}

}  // namespace fsw_app
