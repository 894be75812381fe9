#include "pico_flexx/royale_depth_camera.hpp"

#include <chrono>
#include <royale.hpp>

namespace pico_flexx {

namespace {

// royale's statuses carry royale's numbers, and so do hal's: the value
// crosses unchanged (a status only the vendor's SDK knows keeps its number
// and prints as UNKNOWN_STATUS).
hal::CameraStatus to_hal(royale::CameraStatus status) {
  return static_cast<hal::CameraStatus>(static_cast<int>(status));
}

bool ok(royale::CameraStatus status) {
  return status == royale::CameraStatus::SUCCESS;
}

// A stamp up to 10 s before its arrival is on the host's own clock (as
// capture_clock_map.hpp: a frame may wait 9 s in the camera's FIFO).
constexpr std::int64_t kSameClockUs = 10'000'000;

}  // namespace

class RoyaleDepthCamera::Listener final : public royale::IDepthDataListener {
 public:
  explicit Listener(RoyaleDepthCamera* owner) : owner_(owner) {}
  void onNewData(const royale::DepthData* data) override { owner_->on_depth_data(data); }

 private:
  RoyaleDepthCamera* owner_;
};

RoyaleDepthCamera::RoyaleDepthCamera(const RoyaleCameraConfig& cfg, const hal::Clock& clock)
    : cfg_(cfg), clock_(clock), clock_map_(cfg.capture_clock) {}

RoyaleDepthCamera::~RoyaleDepthCamera() {
  if (device_) {
    bool capturing = false;
    if (ok(device_->isCapturing(capturing)) && capturing) (void)device_->stopCapture();
    (void)device_->unregisterDataListener();
  }
}

hal::CameraStatus RoyaleDepthCamera::initialize() {
  if (device_) return hal::CameraStatus::kDeviceAlreadyInitialized;
  royale::CameraManager manager;
  const royale::Vector<royale::String> ids = manager.getConnectedCameraList();
  if (ids.size() == 0) {
    error_ = "royale lists no camera: check the cable, or that no other process holds the camera";
    return hal::CameraStatus::kCouldNotOpen;
  }
  std::size_t chosen = ids.size();
  for (std::size_t k = 0; k < ids.size() && chosen == ids.size(); ++k) {
    if (cfg_.serial.empty() || cfg_.serial == ids[k].c_str()) chosen = k;
  }
  if (chosen == ids.size()) {
    error_ = "no camera with serial " + cfg_.serial + " among the " + std::to_string(ids.size()) +
             " royale lists (first: " + ids[0].c_str() + ")";
    return hal::CameraStatus::kCouldNotOpen;
  }
  std::unique_ptr<royale::ICameraDevice> device = manager.createCamera(ids[chosen]);
  if (!device) {
    error_ = std::string("royale could not create camera ") + ids[chosen].c_str();
    return hal::CameraStatus::kCouldNotOpen;
  }
  const royale::CameraStatus init = device->initialize();
  if (!ok(init)) {
    error_ = std::string("camera ") + ids[chosen].c_str() +
             ": initialize: " + royale::getStatusString(init).c_str();
    return to_hal(init);
  }
  uint16_t width = 0, height = 0;
  if (!ok(device->getMaxSensorWidth(width)) || !ok(device->getMaxSensorHeight(height)) ||
      width == 0 || height == 0) {
    error_ = std::string("camera ") + ids[chosen].c_str() + " reports no sensor size";
    return hal::CameraStatus::kRuntimeError;
  }
  royale_listener_ = std::make_unique<Listener>(this);
  const royale::CameraStatus reg = device->registerDataListener(royale_listener_.get());
  if (!ok(reg)) {
    error_ = std::string("registerDataListener: ") + royale::getStatusString(reg).c_str();
    return to_hal(reg);
  }
  max_width_ = width;
  max_height_ = height;
  points_ = std::make_unique<hal::DepthPoint[]>(static_cast<std::size_t>(width) * height);
  id_ = ids[chosen].c_str();
  device_ = std::move(device);
  error_.clear();
  return refresh_use_case();
}

// hal names the use cases it knows; one the vendor's SDK adds beyond them
// is set and streamed, but has no hal::UseCase (current_use_case says so).
hal::CameraStatus RoyaleDepthCamera::refresh_use_case() {
  royale::String name;
  const royale::CameraStatus status = device_->getCurrentUseCase(name);
  if (!ok(status)) return to_hal(status);
  use_case_ = hal::find_use_case(name.c_str());
  return hal::CameraStatus::kSuccess;
}

hal::CameraStatus RoyaleDepthCamera::set_use_case(const char* name) {
  if (!device_) return hal::CameraStatus::kDeviceNotInitialized;
  if (name == nullptr) return hal::CameraStatus::kInvalidValue;
  const royale::CameraStatus status = device_->setUseCase(royale::String(name));
  if (!ok(status)) return to_hal(status);
  return refresh_use_case();
}

hal::CameraStatus RoyaleDepthCamera::current_use_case(const hal::UseCase** use_case) const {
  if (!device_) return hal::CameraStatus::kDeviceNotInitialized;
  if (use_case == nullptr) return hal::CameraStatus::kInvalidValue;
  if (use_case_ == nullptr) return hal::CameraStatus::kUseCaseNotSupported;
  *use_case = use_case_;
  return hal::CameraStatus::kSuccess;
}

hal::CameraStatus RoyaleDepthCamera::set_exposure_mode(hal::ExposureMode mode) {
  if (!device_) return hal::CameraStatus::kDeviceNotInitialized;
  return to_hal(device_->setExposureMode(mode == hal::ExposureMode::kAutomatic
                                             ? royale::ExposureMode::AUTOMATIC
                                             : royale::ExposureMode::MANUAL));
}

hal::CameraStatus RoyaleDepthCamera::set_exposure_time(std::uint32_t exposure_us) {
  if (!device_) return hal::CameraStatus::kDeviceNotInitialized;
  return to_hal(device_->setExposureTime(exposure_us));
}

hal::CameraStatus RoyaleDepthCamera::register_data_listener(hal::DepthDataListener* listener) {
  if (listener == nullptr) return hal::CameraStatus::kInvalidValue;
  listener_.store(listener);
  return hal::CameraStatus::kSuccess;
}

hal::CameraStatus RoyaleDepthCamera::start_capture() {
  if (!device_) return hal::CameraStatus::kDeviceNotInitialized;
  if (listener_.load() == nullptr) return hal::CameraStatus::kLogicError;
  return to_hal(device_->startCapture());
}

hal::CameraStatus RoyaleDepthCamera::stop_capture() {
  if (!device_) return hal::CameraStatus::kDeviceNotInitialized;
  return to_hal(device_->stopCapture());
}

hal::CameraStatus RoyaleDepthCamera::lens_parameters(hal::LensParameters* lens) const {
  if (!device_) return hal::CameraStatus::kDeviceNotInitialized;
  if (lens == nullptr) return hal::CameraStatus::kInvalidValue;
  royale::LensParameters p;
  const royale::CameraStatus status = device_->getLensParameters(p);
  if (!ok(status)) return to_hal(status);
  *lens = hal::LensParameters{};
  lens->cx_px = p.principalPoint.first;
  lens->cy_px = p.principalPoint.second;
  lens->fx_px = p.focalLength.first;
  lens->fy_px = p.focalLength.second;
  lens->p1 = p.distortionTangential.first;
  lens->p2 = p.distortionTangential.second;
  // royale gives as many radial terms as the lens model has (k1, k2, k3).
  const std::size_t radial = p.distortionRadial.size();
  if (radial > 0) lens->k1 = p.distortionRadial[0];
  if (radial > 1) lens->k2 = p.distortionRadial[1];
  if (radial > 2) lens->k3 = p.distortionRadial[2];
  return hal::CameraStatus::kSuccess;
}

hal::CameraStatus RoyaleDepthCamera::max_frame_size(std::uint32_t* width,
                                                    std::uint32_t* height) const {
  if (!device_) return hal::CameraStatus::kDeviceNotInitialized;
  if (width == nullptr || height == nullptr) return hal::CameraStatus::kInvalidValue;
  *width = max_width_;
  *height = max_height_;
  return hal::CameraStatus::kSuccess;
}

bool RoyaleDepthCamera::is_connected() const {
  bool connected = false;
  return device_ && ok(device_->isConnected(connected)) && connected;
}

bool RoyaleDepthCamera::is_capturing() const {
  bool capturing = false;
  return device_ && ok(device_->isCapturing(capturing)) && capturing;
}

RoyaleFrameCounts RoyaleDepthCamera::counts() const {
  RoyaleFrameCounts c;
  c.delivered = delivered_.load();
  c.malformed = malformed_.load();
  c.unattended = unattended_.load();
  return c;
}

// On royale's thread: the frame copied into the buffer sized at
// initialize(), nothing allocated.
void RoyaleDepthCamera::on_depth_data(const royale::DepthData* data) {
  const std::int64_t arrival_us = clock_.now_us();
  hal::DepthDataListener* const listener = listener_.load();
  if (data == nullptr) {
    malformed_.fetch_add(1);
    return;
  }
  const std::size_t n = static_cast<std::size_t>(data->width) * data->height;
  if (data->width == 0 || data->width > max_width_ || data->height > max_height_ ||
      data->points.size() != n) {
    malformed_.fetch_add(1);
    return;
  }
  // royale documents its stamps as time since the 1970 epoch (the system
  // clock): a stamp that is not already on the host's monotonic clock is
  // moved there by the two clocks' difference now, exactly for a stamp
  // that is on the system clock. One on yet another clock (a camera's own
  // counter) lands far from its arrival and is mapped by the least delay.
  const std::int64_t raw_stamp_us = static_cast<std::int64_t>(data->timeStamp.count());
  const bool on_host_clock =
      raw_stamp_us <= arrival_us && arrival_us - raw_stamp_us <= kSameClockUs;
  const std::int64_t stamp_us =
      on_host_clock ? raw_stamp_us : raw_stamp_us - hal::system_minus_clock_us(clock_);
  hal::DepthFrame frame;
  frame.frame_id = ++frame_id_;
  frame.capture_time_us = clock_map_.to_host_us(stamp_us, arrival_us);
  capture_clock_.store(clock_map_.clock());
  if (listener == nullptr) {
    unattended_.fetch_add(1);
    return;
  }
  for (std::size_t i = 0; i < n; ++i) {
    const royale::DepthPoint& in = data->points[i];
    hal::DepthPoint& out = points_[i];
    out.x_m = in.x;
    out.y_m = in.y;
    out.z_m = in.z;
    out.noise_m = in.noise;
    out.gray_value = in.grayValue;
    out.confidence = in.depthConfidence;
  }
  frame.width = data->width;
  frame.height = data->height;
  frame.points = points_.get();
  listener->on_new_data(frame);
  delivered_.fetch_add(1);
}

}  // namespace pico_flexx
