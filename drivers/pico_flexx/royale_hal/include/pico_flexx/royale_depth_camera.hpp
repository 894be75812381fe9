#pragma once
// hal::DepthCamera on royale's C++ API, and on nothing else of the
// project's drivers: it builds against the project's royale
// (drivers/pico_flexx/royale, on the USB driver) or against the vendor's
// royale SDK (CMake option HRP_ROYALE_SDK_DIR), unchanged. So the robot
// can fly on the vendor's processing where the team has the SDK, and on
// its own where it has not, with the same application code.
//
// initialize() lists the cameras (royale::CameraManager), takes the one
// with the configured serial number or else the first, initialises it and
// sizes the frame buffer to the sensor; from then on nothing is allocated:
// every royale::DepthData is copied into that buffer and handed to the
// listener as a hal::DepthFrame, with its capture time on the host's
// monotonic clock (capture_clock_map.hpp). A frame larger than the sensor
// or with fewer points than it says is dropped and counted.
#include <atomic>
#include <cstdint>
#include <memory>
#include <string>

#include "hal/clock.hpp"
#include "hal/depth_camera.hpp"
#include "pico_flexx/capture_clock_map.hpp"

namespace royale {
class ICameraDevice;
struct DepthData;
}  // namespace royale

namespace pico_flexx {

struct RoyaleCameraConfig {
  std::string serial;  // the camera's id in royale's list; empty: the first camera
  CaptureClockMapConfig capture_clock;
};

struct RoyaleFrameCounts {
  std::uint64_t delivered = 0;   // handed to the listener
  std::uint64_t malformed = 0;   // dropped: size or point count wrong
  std::uint64_t unattended = 0;  // arrived with no listener registered
};

class RoyaleDepthCamera final : public hal::DepthCamera {
 public:
  RoyaleDepthCamera(const RoyaleCameraConfig& cfg, const hal::Clock& clock);
  ~RoyaleDepthCamera() override;
  RoyaleDepthCamera(const RoyaleDepthCamera&) = delete;
  RoyaleDepthCamera& operator=(const RoyaleDepthCamera&) = delete;

  [[nodiscard]] hal::CameraStatus initialize() override;
  [[nodiscard]] hal::CameraStatus set_use_case(const char* name) override;
  [[nodiscard]] hal::CameraStatus current_use_case(const hal::UseCase** use_case) const override;
  [[nodiscard]] hal::CameraStatus set_exposure_mode(hal::ExposureMode mode) override;
  [[nodiscard]] hal::CameraStatus set_exposure_time(std::uint32_t exposure_us) override;
  [[nodiscard]] hal::CameraStatus register_data_listener(hal::DepthDataListener* listener) override;
  [[nodiscard]] hal::CameraStatus start_capture() override;
  [[nodiscard]] hal::CameraStatus stop_capture() override;
  [[nodiscard]] hal::CameraStatus lens_parameters(hal::LensParameters* lens) const override;
  [[nodiscard]] hal::CameraStatus max_frame_size(std::uint32_t* width,
                                                 std::uint32_t* height) const override;
  bool is_connected() const override;
  bool is_capturing() const override;

  // Why initialize() failed, in words (which camera was looked for, what
  // royale said).
  const std::string& error() const { return error_; }
  // The camera's id (its serial number) once initialised.
  const std::string& id() const { return id_; }
  RoyaleFrameCounts counts() const;
  CaptureClock capture_clock() const { return capture_clock_; }

 private:
  class Listener;  // royale's listener, forwarding to on_depth_data
  void on_depth_data(const royale::DepthData* data);
  hal::CameraStatus refresh_use_case();

  RoyaleCameraConfig cfg_;
  const hal::Clock& clock_;
  std::unique_ptr<royale::ICameraDevice> device_;
  std::unique_ptr<Listener> royale_listener_;
  std::unique_ptr<hal::DepthPoint[]> points_;
  std::uint32_t max_width_ = 0, max_height_ = 0;
  const hal::UseCase* use_case_ = nullptr;
  std::atomic<hal::DepthDataListener*> listener_{nullptr};
  std::string error_, id_;
  // Written on royale's thread only, read for the counts.
  CaptureClockMap clock_map_;
  std::atomic<CaptureClock> capture_clock_{CaptureClock::kUnknown};
  std::atomic<std::uint64_t> delivered_{0}, malformed_{0}, unattended_{0};
  std::uint64_t frame_id_ = 0;
};

}  // namespace pico_flexx
