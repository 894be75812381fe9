#pragma once
// The depth-camera interface, shaped like royale's ICameraDevice so that the
// Pico Flexx driver, the simulated camera and a recording player are
// interchangeable. Every call returns a status; nothing throws.
#include <cstdint>

#include "hal/camera_status.hpp"
#include "hal/depth_frame.hpp"
#include "hal/use_case.hpp"

namespace hal {

class DepthDataListener {
 public:
  virtual ~DepthDataListener() = default;
  // Called on the camera's thread for every frame; must not block.
  virtual void on_new_data(const DepthFrame& frame) = 0;
};

enum class ExposureMode : std::uint8_t { kManual, kAutomatic };

class DepthCamera {
 public:
  virtual ~DepthCamera() = default;

  [[nodiscard]] virtual CameraStatus initialize() = 0;
  [[nodiscard]] virtual CameraStatus set_use_case(const char* name) = 0;
  [[nodiscard]] virtual CameraStatus current_use_case(const UseCase** use_case) const = 0;
  [[nodiscard]] virtual CameraStatus set_exposure_mode(ExposureMode mode) = 0;
  [[nodiscard]] virtual CameraStatus set_exposure_time(std::uint32_t exposure_us) = 0;
  [[nodiscard]] virtual CameraStatus register_data_listener(DepthDataListener* listener) = 0;
  [[nodiscard]] virtual CameraStatus start_capture() = 0;
  [[nodiscard]] virtual CameraStatus stop_capture() = 0;
  [[nodiscard]] virtual CameraStatus lens_parameters(LensParameters* lens) const = 0;
  [[nodiscard]] virtual CameraStatus max_frame_size(std::uint32_t* width,
                                                    std::uint32_t* height) const = 0;
  virtual bool is_connected() const = 0;
  virtual bool is_capturing() const = 0;
};

}  // namespace hal
