#pragma once
// Where fsw_app's depth frames come from, chosen once at start-up:
//   --hal sim, --camera raw    the simulated camera's raw phase frames through
//                              the robot's ToF processing (in-process)
//   --hal sim, --camera depth  the simulated camera's depth renderer
//   --hal sim, --camera usb    the emulated Pico Flexx on umockdev, read by the
//                              robot's USB driver through real libusb
//   --hal sim, --camera royale the same emulated camera through the royale API
//                              (the project's royale, on the same driver)
//   --hal real                 the Pico Flexx driver (first camera found, or
//                              the configuration's serial number), or with
//                              --camera royale the royale API (the vendor's
//                              SDK where the build has it), or
//                              --camera-replay's recorded frames
//   no camera task here        DEPTH_FRAME messages, for an estimator task
#include <cstdint>
#include <memory>
#include <optional>
#include <string>

#include "app_options.hpp"
#include "fsw_app/app_config.hpp"
#include "fsw_app/lcm_depth_camera.hpp"
#include "fsw_app/lcm_hub.hpp"
#include "hal/clock.hpp"
#include "hal/depth_camera.hpp"
#include "pico_flexx/raw_depth_pipeline.hpp"
#include "pico_flexx/royale_depth_camera.hpp"
#include "pico_flexx/usb_depth_camera.hpp"
#include "run_summary.hpp"
#ifdef HRP_WITH_SIM
#include "hil_usb_camera.hpp"
#include "hil_world.hpp"
#endif

namespace sim_hal {
struct Scenario;
}

namespace fsw_app {

class HilWorld;

class CameraSource {
 public:
  CameraSource() = default;
  ~CameraSource();
  CameraSource(const CameraSource&) = delete;
  CameraSource& operator=(const CameraSource&) = delete;

  // nullptr when neither a camera task nor an estimator task runs here.
  hal::DepthCamera* camera() const { return camera_; }
  LcmDepthCamera* lcm_camera() const { return lcm_camera_; }
  // Why the camera's initialize() failed, when the camera says more than
  // its status (the USB driver does); empty otherwise.
  std::string failure_detail() const;
  // The camera's share of the run's summary: the ToF processing's figures
  // on the raw and USB paths, the driver's counts on the USB path, royale's
  // on the royale path.
  void report(RunSummary* summary) const;
  // Settings made once the camera is initialised and its use case set:
  // through royale, the camera's automatic exposure (the USB driver takes
  // it from its configuration).
  hal::CameraStatus configure_after_use_case();

#ifdef HRP_WITH_SIM
  // The USB path's HIL rig, for its faults; nullptr on any other path.
  HilUsbCamera* hil_usb() const {
    return hil_usb_.get();
  }
#endif

 private:
  friend std::optional<int> open_camera_source(const Options& opt, const AppConfig& cfg,
                                               LcmHub& hub, HilWorld* world,
                                               const sim_hal::Scenario* scenario,
                                               const hal::Clock& clock, CameraSource* out);
  const pico_flexx::RawDepthPipeline* processing() const;

  hal::DepthCamera* camera_ = nullptr;
  LcmDepthCamera* lcm_camera_ = nullptr;
  std::unique_ptr<hal::DepthCamera> owned_;
  // The raw path's processing (the in-process simulated camera's).
  std::unique_ptr<pico_flexx::RawDepthPipeline> tof_pipeline_;
  // The USB driver, on the robot (--hal real) ...
  pico_flexx::UsbDepthCamera* usb_driver_ = nullptr;
  std::string usb_serial_;  // the one it looks for (empty: any)
  // ... or the royale API on the robot.
  pico_flexx::RoyaleDepthCamera* royale_ = nullptr;
#ifdef HRP_WITH_SIM
  // ... or in the HIL rig.
  std::unique_ptr<HilUsbCamera> hil_usb_;
#endif
};

// The driver's settings from the configuration: the use case it keeps
// across reconnects and the serial number to look for.
pico_flexx::UsbCameraConfig usb_camera_config(const AppConfig& cfg);

// Builds *out for this run. `world` and `scenario` are the HilWorld and
// sim_hal::Scenario of a --hal sim run (nullptr otherwise). Returns an exit
// status after printing why, when the run cannot go on.
std::optional<int> open_camera_source(const Options& opt, const AppConfig& cfg, LcmHub& hub,
                                      HilWorld* world, const sim_hal::Scenario* scenario,
                                      const hal::Clock& clock, CameraSource* out);

}  // namespace fsw_app
