#include "camera_source.hpp"

#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "fsw_app/estimator_task.hpp"
#include "hal/use_case.hpp"
#include "replay_camera/pcd_replay_camera.hpp"

namespace fsw_app {

static_assert(kCameraSerialChars == pico_flexx::kSerialBytes,
              "the configuration's camera serial and the USB protocol's disagree");

namespace {

#ifdef HRP_WITH_SIM
// The raw path in-process: the simulated unit writes its calibration file,
// the robot's processing reads it, as on the robot at start-up.
std::optional<int> open_raw_path(const Options& opt, HilWorld& world, const hal::Clock& clock,
                                 std::unique_ptr<pico_flexx::RawDepthPipeline>* pipeline) {
  std::string path = opt.tof_calibration;
  if (path.empty()) {
    const char* tmp = std::getenv("TMPDIR");
    path = std::string(tmp && *tmp ? tmp : "/tmp") + "/fsw_app-tof-unit-" +
           std::to_string(getpid()) + ".json";
  }
  std::string error;
  if (!world.camera().write_unit_calibration(path, &error)) {
    std::fprintf(stderr, "fsw_app: the simulated camera's calibration: %s\n", error.c_str());
    return 2;
  }
  *pipeline =
      pico_flexx::open_raw_depth_pipeline(path, pico_flexx::PipelineConfig{}, clock, &error);
  if (opt.tof_calibration.empty()) std::remove(path.c_str());
  if (!*pipeline) {
    std::fprintf(stderr, "fsw_app: ToF calibration: %s\n", error.c_str());
    return 2;
  }
  if (world.camera().set_raw_pipeline(pipeline->get()) != hal::CameraStatus::kSuccess) {
    std::fprintf(stderr, "fsw_app: the simulated camera refused the raw path\n");
    return 1;
  }
  return std::nullopt;
}
#endif

std::optional<int> open_replay(const Options& opt, const hal::Clock& clock,
                               std::unique_ptr<hal::DepthCamera>* owned) {
  const EstimatorTaskConfig defaults;
  auto replay = std::make_unique<replay_camera::PcdReplayCamera>(
      opt.camera_replay, clock, true,
      static_cast<std::uint64_t>(defaults.max_width) * defaults.max_height);
  std::string error;
  if (!replay->load(&error)) {
    std::fprintf(stderr, "fsw_app: %s\n", error.c_str());
    return 2;
  }
  // The files that would not read are named; the others play.
  if (!error.empty()) {
    std::fprintf(stderr, "fsw_app: --camera-replay: %zu frames; skipped:\n%s",
                 replay->frame_count(), error.c_str());
  }
  *owned = std::move(replay);
  return std::nullopt;
}

}  // namespace

pico_flexx::UsbCameraConfig usb_camera_config(const AppConfig& cfg) {
  pico_flexx::UsbCameraConfig usb;
  std::size_t count = 0;
  const hal::UseCase* all = hal::use_cases(&count);
  const hal::UseCase* wanted = hal::find_use_case(cfg.use_case);
  if (wanted != nullptr) usb.use_case_index = static_cast<std::uint8_t>(wanted - all);
  std::strncpy(usb.serial, cfg.camera_serial.c_str(), pico_flexx::kSerialBytes);
  // The camera's automatic exposure, as the simulated camera runs it: a
  // fixed exposure set for one range is too dark or saturated at another
  // over an approach from a metre to the bar.
  usb.exposure_automatic = true;
  return usb;
}

CameraSource::~CameraSource() {
  if (camera_ != nullptr) (void)camera_->stop_capture();
#ifdef HRP_WITH_SIM
  hil_usb_.reset();  // the driver first, then the emulated device
#endif
  owned_.reset();
}

const pico_flexx::RawDepthPipeline* CameraSource::processing() const {
  if (tof_pipeline_) return tof_pipeline_.get();
  if (usb_driver_ != nullptr) return usb_driver_->pipeline();
#ifdef HRP_WITH_SIM
  if (hil_usb_) return hil_usb_->pipeline();
#endif
  return nullptr;
}

std::string CameraSource::failure_detail() const {
  if (royale_ != nullptr) {
    return royale_->error() + " (the royale API on this build: " HRP_ROYALE_API_NAME
                              "; or play recorded frames with --camera-replay DIR)";
  }
  if (usb_driver_ != nullptr) {
    std::string detail = usb_driver_->error();
    if (detail.find("NOT_FOUND") != std::string::npos) {
      detail += " (no Pico Flexx, USB 1c28:c012";
      if (!usb_serial_.empty()) detail += " with serial " + usb_serial_;
      detail +=
          ", on the bus: check the cable and the device node's permissions, or play recorded "
          "frames with --camera-replay DIR)";
    }
    return detail;
  }
#ifdef HRP_WITH_SIM
  if (hil_usb_) return hil_usb_->driver_error();
#endif
  return "";
}

void CameraSource::report(RunSummary* summary) const {
  if (const pico_flexx::RawDepthPipeline* p = processing()) {
    summary->tof = p->counts();
    summary->tof_median_us = p->processing_median_us();
  }
  if (usb_driver_ != nullptr) {
    summary->usb = usb_path_report(usb_driver_->usb());
  }
  if (royale_ != nullptr) summary->royale = royale_path_report(*royale_);
#ifdef HRP_WITH_SIM
  if (hil_usb_) {
    if (hil_usb_->through_royale()) {
      summary->royale = hil_usb_->royale_report();
    } else {
      summary->usb = hil_usb_->report();
    }
  }
#endif
}

hal::CameraStatus CameraSource::configure_after_use_case() {
  bool through_royale = royale_ != nullptr;
#ifdef HRP_WITH_SIM
  through_royale = through_royale || (hil_usb_ && hil_usb_->through_royale());
#endif
  if (!through_royale || camera_ == nullptr) return hal::CameraStatus::kSuccess;
  // The automatic exposure, as on the USB path (usb_camera_config).
  return camera_->set_exposure_mode(hal::ExposureMode::kAutomatic);
}

std::optional<int> open_camera_source(const Options& opt, const AppConfig& cfg, LcmHub& hub,
                                      HilWorld* world, const sim_hal::Scenario* scenario,
                                      const hal::Clock& clock, CameraSource* out) {
  if (!opt.runs(kCameraTask)) {
    if (!opt.runs(kEstimatorTask)) return std::nullopt;
    // An estimator here without the camera: frames over LCM.
    const EstimatorTaskConfig defaults;
    auto from_lcm = std::make_unique<LcmDepthCamera>(hub, defaults.max_width, defaults.max_height);
    out->lcm_camera_ = from_lcm.get();
    out->owned_ = std::move(from_lcm);
    out->camera_ = out->owned_.get();
    return std::nullopt;
  }
  if (opt.hal == "real") {
    if (!opt.camera_replay.empty()) {
      if (auto rc = open_replay(opt, clock, &out->owned_)) return rc;
    } else if (opt.camera == "royale") {
      pico_flexx::RoyaleCameraConfig royale;
      royale.serial = cfg.camera_serial;
      auto camera = std::make_unique<pico_flexx::RoyaleDepthCamera>(royale, clock);
      out->royale_ = camera.get();
      out->owned_ = std::move(camera);
    } else {
      auto driver = std::make_unique<pico_flexx::UsbDepthCamera>(
          usb_camera_config(cfg), pico_flexx::PipelineConfig{}, clock);
      out->usb_driver_ = driver.get();
      out->usb_serial_ = cfg.camera_serial;
      out->owned_ = std::move(driver);
    }
    out->camera_ = out->owned_.get();
    return std::nullopt;
  }
#ifdef HRP_WITH_SIM
  if (world == nullptr || scenario == nullptr) return 1;  // needs_sim_world() said otherwise
  if (opt.camera == "usb" || opt.camera == "royale") {
    out->hil_usb_ = std::make_unique<HilUsbCamera>(*scenario, *world, clock, scenario->seed);
    std::string error;
    if (!out->hil_usb_->plug_in(usb_camera_config(cfg), opt.camera == "royale", &error)) {
      std::fprintf(stderr, "fsw_app: the emulated Pico Flexx: %s\n", error.c_str());
      return 1;
    }
    out->camera_ = &out->hil_usb_->camera();
    return std::nullopt;
  }
  out->camera_ = &world->camera();
  if (opt.camera == "raw") return open_raw_path(opt, *world, clock, &out->tof_pipeline_);
  return std::nullopt;
#else
  (void)world;
  (void)scenario;
  std::fprintf(stderr,
               "fsw_app: this build has no simulated HAL (a robot build); use --hal real\n");
  return 2;
#endif
}

}  // namespace fsw_app
