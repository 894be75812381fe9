#include "pico_flexx/usb_depth_camera.hpp"

#include <memory>

#include "tof/calibration_io.hpp"

namespace pico_flexx {

hal::CameraStatus to_camera_status(UsbStatus status) {
  switch (status) {
    case UsbStatus::kOk:
      return hal::CameraStatus::kSuccess;
    case UsbStatus::kNotFound:
      return hal::CameraStatus::kCouldNotOpen;
    case UsbStatus::kNoDevice:
      return hal::CameraStatus::kDisconnected;
    case UsbStatus::kAccessDenied:
      return hal::CameraStatus::kInsufficientPrivileges;
    case UsbStatus::kBusy:
      return hal::CameraStatus::kDeviceIsBusy;
    case UsbStatus::kTimeout:
      return hal::CameraStatus::kTimeout;
    case UsbStatus::kRefused:
      return hal::CameraStatus::kInvalidValue;
    case UsbStatus::kNotOpen:
      return hal::CameraStatus::kDeviceNotInitialized;
    case UsbStatus::kStreaming:
      return hal::CameraStatus::kDeviceIsBusy;
    case UsbStatus::kNotStreaming:
      return hal::CameraStatus::kLogicError;
    case UsbStatus::kBadArgument:
      return hal::CameraStatus::kInvalidValue;
    case UsbStatus::kNoMemory:
      return hal::CameraStatus::kResourceError;
    case UsbStatus::kStall:
    case UsbStatus::kIoError:
    case UsbStatus::kBadReply:
    case UsbStatus::kLibusbError:
      return hal::CameraStatus::kRuntimeError;
  }
  return hal::CameraStatus::kRuntimeError;
}

UsbDepthCamera::UsbDepthCamera(const UsbCameraConfig& usb, const PipelineConfig& processing,
                               const hal::Clock& clock)
    : usb_(usb, clock), processing_(processing), clock_(clock) {}

hal::CameraStatus UsbDepthCamera::initialize() {
  if (pipeline_) return hal::CameraStatus::kDeviceAlreadyInitialized;
  UsbStatus s = usb_.open();
  if (s != UsbStatus::kOk) {
    error_ = std::string("Pico Flexx over USB: open: ") + to_string(s);
    return to_camera_status(s);
  }
  std::string text(kMaxCalibrationBytes, '\0');
  std::size_t bytes = 0;
  s = usb_.read_calibration(reinterpret_cast<std::uint8_t*>(&text[0]), text.size(), &bytes);
  if (s != UsbStatus::kOk) {
    error_ = std::string("Pico Flexx over USB: reading the calibration: ") + to_string(s);
    return s == UsbStatus::kBadReply ? hal::CameraStatus::kCalibrationDataError
                                     : to_camera_status(s);
  }
  text.resize(bytes);
  tof::Calibration calibration;
  const std::string name = std::string("camera ") + usb_.identity().serial + " calibration";
  if (!tof::parse_calibration(text, name, &calibration, &error_)) {
    return hal::CameraStatus::kCalibrationDataError;
  }
  auto pipeline = std::make_unique<RawDepthPipeline>(calibration, processing_, clock_);
  if (pipeline->init_status() != PipelineStatus::kOk) {
    error_ = std::string("Pico Flexx over USB: the processing refused the calibration: ") +
             to_string(pipeline->init_status());
    return hal::CameraStatus::kCalibrationDataError;
  }
  pipeline->set_listener(listener_);
  pipeline_ = std::move(pipeline);
  return hal::CameraStatus::kSuccess;
}

hal::CameraStatus UsbDepthCamera::set_use_case(const char* name) {
  std::size_t count = 0;
  const hal::UseCase* all = hal::use_cases(&count);
  const hal::UseCase* use_case = hal::find_use_case(name);
  if (use_case == nullptr) return hal::CameraStatus::kUseCaseNotSupported;
  if (!pipeline_) return hal::CameraStatus::kDeviceNotInitialized;
  return to_camera_status(usb_.set_use_case(static_cast<std::uint8_t>(use_case - all)));
}

hal::CameraStatus UsbDepthCamera::current_use_case(const hal::UseCase** use_case) const {
  std::size_t count = 0;
  *use_case = &hal::use_cases(&count)[usb_.use_case_index()];
  return hal::CameraStatus::kSuccess;
}

hal::CameraStatus UsbDepthCamera::set_exposure_mode(hal::ExposureMode mode) {
  if (!pipeline_) return hal::CameraStatus::kDeviceNotInitialized;
  return to_camera_status(usb_.set_exposure_mode(mode == hal::ExposureMode::kAutomatic));
}

hal::CameraStatus UsbDepthCamera::set_exposure_time(std::uint32_t exposure_us) {
  if (!pipeline_) return hal::CameraStatus::kDeviceNotInitialized;
  const UsbStatus s = usb_.set_exposure_time(exposure_us);
  if (s == UsbStatus::kRefused) {
    return usb_.last_refusal() == ReplyStatus::kWrongMode
               ? hal::CameraStatus::kExposureModeInvalid
               : hal::CameraStatus::kExposureTimeNotSupported;
  }
  return to_camera_status(s);
}

hal::CameraStatus UsbDepthCamera::register_data_listener(hal::DepthDataListener* listener) {
  if (is_capturing()) return hal::CameraStatus::kDeviceIsBusy;
  listener_ = listener;
  if (pipeline_) pipeline_->set_listener(listener);
  return hal::CameraStatus::kSuccess;
}

hal::CameraStatus UsbDepthCamera::start_capture() {
  if (!pipeline_) return hal::CameraStatus::kDeviceNotInitialized;
  return to_camera_status(usb_.start_streaming(this));
}

hal::CameraStatus UsbDepthCamera::stop_capture() {
  return to_camera_status(usb_.stop_streaming());
}

hal::CameraStatus UsbDepthCamera::lens_parameters(hal::LensParameters* lens) const {
  if (!pipeline_) return hal::CameraStatus::kDeviceNotInitialized;
  *lens = pipeline_->lens();
  return hal::CameraStatus::kSuccess;
}

hal::CameraStatus UsbDepthCamera::max_frame_size(std::uint32_t* width,
                                                 std::uint32_t* height) const {
  *width = tof::kWidthPx;
  *height = tof::kHeightPx;
  return hal::CameraStatus::kSuccess;
}

bool UsbDepthCamera::is_connected() const {
  const CameraState s = usb_.state();
  return s == CameraState::kOpen || s == CameraState::kStreaming || s == CameraState::kRecovering;
}

bool UsbDepthCamera::is_capturing() const {
  // Also while the driver brings a lost or unplugged camera back: the
  // capture stands until stop_capture(), which must then be let through.
  return usb_.state() != CameraState::kClosed && usb_.capture_requested();
}

void UsbDepthCamera::on_raw_frame(const RawFrameInfo&, const tof::RawFrame& frame) {
  delivering_exposure_us_ = frame.exposure_us;
  delivering_frequencies_ = tof::frequency_count(frame.mode);
  (void)pipeline_->on_raw_frame(frame);
}

}  // namespace pico_flexx
