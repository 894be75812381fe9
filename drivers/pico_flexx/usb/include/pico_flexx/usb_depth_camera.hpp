#pragma once
// hal::DepthCamera on the Pico Flexx over USB: the USB driver's raw frames
// through the robot's ToF processing (raw_depth_pipeline.hpp) to the
// registered listener. initialize() opens the camera, reads the unit's
// calibration file from it (CALIBRATION_INFO, READ_CALIBRATION) and builds
// the processing on it; after that nothing is allocated per frame.
#include <memory>
#include <string>

#include "hal/depth_camera.hpp"
#include "pico_flexx/raw_depth_pipeline.hpp"
#include "pico_flexx/usb_camera.hpp"

namespace pico_flexx {

// The USB driver's status as the depth-camera interface's (royale's codes).
hal::CameraStatus to_camera_status(UsbStatus status);

class UsbDepthCamera final : public hal::DepthCamera, private RawFrameListener {
 public:
  // The largest calibration file read from a camera (the per-pixel table
  // makes it about 250 kB).
  static constexpr std::size_t kMaxCalibrationBytes = 1024 * 1024;

  UsbDepthCamera(const UsbCameraConfig& usb, const PipelineConfig& processing,
                 const hal::Clock& clock);

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

  // Why initialize() failed, naming what (the calibration's key and line).
  const std::string& error() const { return error_; }
  UsbCamera& usb() { return usb_; }
  const UsbCamera& usb() const { return usb_; }
  const RawDepthPipeline* pipeline() const { return pipeline_.get(); }
  // The raw frame behind the depth frame being delivered: read them in the
  // listener's call (the royale layer reports them with the frame).
  std::uint32_t delivering_exposure_us() const { return delivering_exposure_us_; }
  int delivering_frequencies() const { return delivering_frequencies_; }

 private:
  void on_raw_frame(const RawFrameInfo& info, const tof::RawFrame& frame) override;

  UsbCamera usb_;
  PipelineConfig processing_;
  const hal::Clock& clock_;
  std::unique_ptr<RawDepthPipeline> pipeline_;
  hal::DepthDataListener* listener_ = nullptr;
  std::string error_;
  std::uint32_t delivering_exposure_us_ = 0;
  int delivering_frequencies_ = 0;
};

}  // namespace pico_flexx
