#include "fsw_app/lcm_depth_camera.hpp"

namespace fsw_app {

LcmDepthCamera::LcmDepthCamera(LcmHub& hub, std::uint32_t max_width, std::uint32_t max_height,
                               const char* channel)
    : max_width_(max_width),
      max_height_(max_height),
      points_(new hal::DepthPoint[static_cast<std::size_t>(max_width) * max_height]) {
  reserve_points(&msg_, static_cast<std::size_t>(max_width) * max_height);
  hub.subscribe(channel, this);
}

hal::CameraStatus LcmDepthCamera::initialize() {
  if (initialized_) return hal::CameraStatus::kDeviceAlreadyInitialized;
  initialized_ = true;
  std::size_t n = 0;
  use_case_ = &hal::use_cases(&n)[0];
  return hal::CameraStatus::kSuccess;
}

hal::CameraStatus LcmDepthCamera::set_use_case(const char* name) {
  if (!initialized_) return hal::CameraStatus::kDeviceNotInitialized;
  if (capturing_) return hal::CameraStatus::kDeviceIsBusy;
  const hal::UseCase* u = name ? hal::find_use_case(name) : nullptr;
  if (!u) return hal::CameraStatus::kUseCaseNotSupported;
  use_case_ = u;
  return hal::CameraStatus::kSuccess;
}

hal::CameraStatus LcmDepthCamera::current_use_case(const hal::UseCase** use_case) const {
  if (!initialized_) return hal::CameraStatus::kDeviceNotInitialized;
  *use_case = use_case_;
  return hal::CameraStatus::kSuccess;
}

hal::CameraStatus LcmDepthCamera::set_exposure_mode(hal::ExposureMode) {
  // The exposure belongs to the camera at the other end.
  return hal::CameraStatus::kNotImplemented;
}

hal::CameraStatus LcmDepthCamera::set_exposure_time(std::uint32_t) {
  return hal::CameraStatus::kNotImplemented;
}

hal::CameraStatus LcmDepthCamera::register_data_listener(hal::DepthDataListener* listener) {
  if (capturing_) return hal::CameraStatus::kDeviceIsBusy;
  listener_ = listener;
  return hal::CameraStatus::kSuccess;
}

hal::CameraStatus LcmDepthCamera::start_capture() {
  if (!initialized_) return hal::CameraStatus::kDeviceNotInitialized;
  capturing_ = true;
  return hal::CameraStatus::kSuccess;
}

hal::CameraStatus LcmDepthCamera::stop_capture() {
  capturing_ = false;
  return hal::CameraStatus::kSuccess;
}

hal::CameraStatus LcmDepthCamera::lens_parameters(hal::LensParameters*) const {
  // Frames carry points already in metres; no lens model travels with them.
  return hal::CameraStatus::kNoCalibrationData;
}

hal::CameraStatus LcmDepthCamera::max_frame_size(std::uint32_t* width,
                                                 std::uint32_t* height) const {
  *width = max_width_;
  *height = max_height_;
  return hal::CameraStatus::kSuccess;
}

namespace {

InputReject input_reject_of(FrameMsgStatus status) {
  switch (status) {
    case FrameMsgStatus::kTrailingBytes:
      return InputReject::kTrailingBytes;
    case FrameMsgStatus::kBadSize:
    case FrameMsgStatus::kTooLarge:
      return InputReject::kOutOfRange;
    default:
      return InputReject::kUndecodable;
  }
}

}  // namespace

void LcmDepthCamera::deliver(const void* data, std::uint32_t size, std::int64_t /*now_us*/) {
  if (!capturing_.load() || listener_ == nullptr) return;
  const FrameMsgStatus status =
      decode_depth_frame(data, size, static_cast<std::size_t>(max_width_) * max_height_, &msg_);
  hal::DepthFrame frame;
  if (status == FrameMsgStatus::kOk) {
    from_msg(msg_, points_.get(), &frame);
    delivered_.fetch_add(1);
    counts_.accepted.fetch_add(1, std::memory_order_relaxed);
  } else {
    counts_.count_rejected(input_reject_of(status));
    // The frame's header fields may be garbage too: pass on no points, so
    // that the camera task drops and counts it.
    last_rejection_.store(status);
    rejected_.fetch_add(1);
  }
  listener_->on_new_data(frame);
}

}  // namespace fsw_app
