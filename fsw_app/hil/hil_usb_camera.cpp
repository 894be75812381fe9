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
      world_frames_(scenario.scene, world, renderer_, clock, seed),
      covered_frames_(nothing_, world, renderer_, clock, seed) {}

HilUsbCamera::~HilUsbCamera() {
  // The driver lets go of the device before the device goes.
  if (driver_) (void)driver_->stop_capture();
  driver_.reset();
  device_.reset();
}

bool HilUsbCamera::plug_in(const pico_flexx::UsbCameraConfig& usb, std::string* error) {
  sim_hal::EmulatedCameraConfig device_config;
  device_config.calibration = tof::calibration_to_json(world_.camera().unit_calibration());
  device_ = sim_hal::EmulatedPicoFlexx::create(device_config, this, clock_, error);
  if (!device_) return false;
  driver_ = std::make_unique<pico_flexx::UsbDepthCamera>(usb, pico_flexx::PipelineConfig{}, clock_);
  return true;
}

void HilUsbCamera::fill(std::uint64_t frame_index, const hal::UseCase& use_case,
                        std::uint32_t exposure_us, tof::RawFrame* out) {
  // umockdev's worker thread, when a frame is due.
  if (world_.occluded(clock_.now_us())) {
    covered_frames_.fill(frame_index, use_case, exposure_us, out);
  } else {
    world_frames_.fill(frame_index, use_case, exposure_us, out);
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

UsbPathReport HilUsbCamera::report() const {
  UsbPathReport r = usb_path_report(driver_->usb());
  const sim_hal::EmulatorCounts device = device_->counts();
  r.frames_made_by_camera =
      static_cast<std::int64_t>(device.frames_sent + device.frames_dropped_no_transfer);
  return r;
}

}  // namespace fsw_app
