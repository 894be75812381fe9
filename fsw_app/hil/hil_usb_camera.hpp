#pragma once
// The hardware-in-loop camera over USB (host only, `--hal sim --camera
// usb`): the simulated world rendered as raw phase frames into the emulated
// Pico Flexx (sim_hal/emulated_pico_flexx.hpp), and the robot's own driver
// reading it through real libusb, the calibration file read from the
// camera, the robot's ToF processing, hal::DepthCamera
// (pico_flexx/usb_depth_camera.hpp). What the camera task gets is what it
// would get from the Pico Flexx on the robot's USB port.
//
// The process must run under umockdev's preload library
// (sim_hal/umockdev_preload.hpp re-executes it so). Faults act where they
// would on the robot: the cable pulled and plugged back, the stream
// endpoint halted, corrupt frames on the wire, a covered lens.
#include <cstdint>
#include <memory>
#include <string>

#include "fsw_app/royale_path_report.hpp"
#include "fsw_app/usb_path_report.hpp"
#include "hal/clock.hpp"
#include "hil_world.hpp"
#include "pico_flexx/royale_depth_camera.hpp"
#include "pico_flexx/usb_depth_camera.hpp"
#include "sim_hal/emulated_pico_flexx.hpp"
#include "sim_hal/rendered_frame_source.hpp"
#include "sim_hal/scenario.hpp"
#include "sim_hal/tof_raw_renderer.hpp"

namespace fsw_app {

class HilUsbCamera final : private sim_hal::RawFrameSource {
 public:
  // None owned; all must outlive this. `seed` seeds the renderer's noise.
  HilUsbCamera(const sim_hal::Scenario& scenario, HilWorld& world, const hal::Clock& clock,
               std::uint64_t seed);
  ~HilUsbCamera() override;
  HilUsbCamera(const HilUsbCamera&) = delete;
  HilUsbCamera& operator=(const HilUsbCamera&) = delete;

  // Plugs the emulated camera in, carrying the world camera's unit
  // calibration as its calibration file, and builds the driver on `usb`;
  // or, `through_royale`, hal::DepthCamera on the royale API (the
  // project's royale, on the same driver inside; `usb.serial` picks the
  // camera). False with *error saying why (not under the preload library,
  // ...).
  bool plug_in(const pico_flexx::UsbCameraConfig& usb, bool through_royale, std::string* error);

  hal::DepthCamera& camera();
  // The driver's ToF processing; nullptr through royale (royale keeps it).
  const pico_flexx::RawDepthPipeline* pipeline() const;
  const std::string& driver_error() const;

  // Faults. The cable out for `out_us`, then back in (replugged by
  // service()); the stream endpoint halted (a clear halt lifts it); the
  // next `frames` frames corrupted on the wire.
  void unplug_for(std::int64_t now_us, std::int64_t out_us);
  void stall_stream() { device_->stall_stream(false); }
  void corrupt_next_frames(int frames) { device_->corrupt_next_frames(frames); }
  // Called every few tens of milliseconds by the run: plugs the cable back
  // in when it is due. False (with *error) when the replug failed.
  bool service(std::int64_t now_us, std::string* error);

  // The driver's account (the USB path), or, through royale, what royale
  // delivered with the camera's own count of frames made.
  UsbPathReport report() const;
  RoyalePathReport royale_report() const;
  bool through_royale() const { return royale_ != nullptr; }

 private:
  // The emulated camera's frames: the world from the flyer's true pose, or
  // nothing while the world says the lens is covered.
  void fill(std::uint64_t frame_index, std::int64_t capture_host_us, const hal::UseCase& use_case,
            std::uint32_t exposure_us, tof::RawFrame* out) override;

  HilWorld& world_;
  const hal::Clock& clock_;
  sim_hal::Scene nothing_;  // what a covered lens sees
  sim_hal::RawRenderer renderer_;
  sim_hal::RenderedFrameSource world_frames_;
  sim_hal::RenderedFrameSource covered_frames_;
  std::unique_ptr<sim_hal::EmulatedPicoFlexx> device_;
  std::unique_ptr<pico_flexx::UsbDepthCamera> driver_;
  std::unique_ptr<pico_flexx::RoyaleDepthCamera> royale_;
  std::int64_t replug_at_us_ = -1;  // -1: plugged in
};

}  // namespace fsw_app
