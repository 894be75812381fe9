#include "hil_usb_camera.hpp"

#include "sim_hal/camera_model.hpp"
#include "tof/calibration_io.hpp"

namespace fsw_app {

HilUsbCamera::HilUsbCamera(const sim_hal::Scenario& scenario, HilWorld& world,
                           const hal::Clock& clock, std::uint64_t seed)
    : world_(world),
      clock_(clock),
      // The same unit as the world's own camera: its lens, its sensor
      // settings and its calibration, so that the USB path and the raw
      // path in-process see the same camera.
      renderer_(sim_hal::pico_flexx_intrinsics(), scenario.sensor, sim_hal::RawRenderSettings{},
                world.camera().unit_calibration()),
      world_frames_(scenario.scene, world, renderer_, seed),
      covered_frames_(nothing_, world, renderer_, seed) {}

HilUsbCamera::~HilUsbCamera() {
  // The driver lets go of the device before the device goes.
  if (driver_) (void)driver_->stop_capture();
  if (royale_) (void)royale_->stop_capture();
  driver_.reset();
  royale_.reset();
  device_.reset();
}

bool HilUsbCamera::plug_in(const pico_flexx::UsbCameraConfig& usb, bool through_royale,
                           std::string* error) {
  sim_hal::EmulatedCameraConfig device_config;
  device_config.calibration = tof::calibration_to_json(world_.camera().unit_calibration());
  device_ = sim_hal::EmulatedPicoFlexx::create(device_config, this, clock_, error);
  if (!device_) return false;
  if (through_royale) {
    pico_flexx::RoyaleCameraConfig royale;
    royale.serial = usb.serial;
    royale_ = std::make_unique<pico_flexx::RoyaleDepthCamera>(royale, clock_);
  } else {
    driver_ =
        std::make_unique<pico_flexx::UsbDepthCamera>(usb, pico_flexx::PipelineConfig{}, clock_);
  }
  return true;
}

hal::DepthCamera& HilUsbCamera::camera() {
  if (royale_) return *royale_;
  return *driver_;
}

const pico_flexx::RawDepthPipeline* HilUsbCamera::pipeline() const {
  return driver_ ? driver_->pipeline() : nullptr;
}

const std::string& HilUsbCamera::driver_error() const {
  return royale_ ? royale_->error() : driver_->error();
}

void HilUsbCamera::fill(std::uint64_t frame_index, std::int64_t capture_host_us,
                        const hal::UseCase& use_case, std::uint32_t exposure_us,
                        tof::RawFrame* out) {
  // umockdev's worker thread, when a frame is sent.
  if (world_.occluded(capture_host_us)) {
    covered_frames_.fill(frame_index, capture_host_us, use_case, exposure_us, out);
  } else {
    world_frames_.fill(frame_index, capture_host_us, use_case, exposure_us, out);
  }
}

void HilUsbCamera::unplug_for(std::int64_t now_us, std::int64_t out_us) {
  device_->unplug();
  replug_at_us_ = now_us + out_us;
}

bool HilUsbCamera::service(std::int64_t now_us, std::string* error) {
  if (replug_at_us_ < 0 || now_us < replug_at_us_) return true;
  replug_at_us_ = -1;
  return device_->replug(error);
}

namespace {
std::int64_t frames_made(const sim_hal::EmulatorCounts& device) {
  return static_cast<std::int64_t>(device.frames_sent + device.frames_dropped_no_transfer);
}
}  // namespace

UsbPathReport HilUsbCamera::report() const {
  UsbPathReport r;
  if (driver_) r = usb_path_report(driver_->usb());
  r.frames_made_by_camera = frames_made(device_->counts());
  return r;
}

RoyalePathReport HilUsbCamera::royale_report() const {
  RoyalePathReport r;
  if (royale_) r = royale_path_report(*royale_);
  r.frames_made_by_camera = frames_made(device_->counts());
  return r;
}

}  // namespace fsw_app
