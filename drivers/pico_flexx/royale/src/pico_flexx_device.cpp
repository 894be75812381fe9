#include "pico_flexx_device.hpp"

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <memory>
#include <string>
#include <thread>

#include "hal/clock.hpp"
#include "hal/use_case.hpp"
#include "tof/raw_frame.hpp"

namespace royale {
namespace {

// The values are the same (Status.hpp): only the type changes.
royale::CameraStatus from_hal(hal::CameraStatus status) {
  return static_cast<royale::CameraStatus>(static_cast<int>(status));
}

// This camera has one stream per use case. Its frames carry royale's id
// for a use case's first stream (0xdefa: never 0, which royale's calls
// take as "the only stream"); a call may name it either way.
constexpr royale::StreamId kStream = 0xdefa;

bool names_the_stream(royale::StreamId id) {
  return id == 0 || id == kStream;
}

// royale stamps a frame with its capture time since the 1970 epoch; the
// driver's is on the host's monotonic clock.
std::int64_t epoch_us_of(std::int64_t monotonic_us, const hal::Clock& clock) {
  return monotonic_us + hal::system_minus_clock_us(clock);
}

constexpr int kDepthDataVersion = 1;

}  // namespace

PicoFlexxDevice::PicoFlexxDevice(const pico_flexx::UsbCameraConfig& usb, const royale::String& id)
    : id_(id), camera_(usb, pico_flexx::PipelineConfig{}, clock_) {}

PicoFlexxDevice::~PicoFlexxDevice() {
  // Before the members go: no event and no frame may be delivered into a
  // half-destroyed device.
  watching_ = false;
  if (watcher_.joinable()) watcher_.join();
  if (camera_.is_capturing()) (void)camera_.stop_capture();
}

royale::CameraStatus PicoFlexxDevice::initialize() {
  if (initialized_) return royale::CameraStatus::DEVICE_ALREADY_INITIALIZED;
  const hal::CameraStatus s = camera_.initialize();
  if (s != hal::CameraStatus::kSuccess) return from_hal(s);
  // Every buffer a frame needs, now: a frame only copies into them.
  data_.version = kDepthDataVersion;
  data_.streamId = kStream;
  data_.points.resize(tof::kPixels);
  data_.exposureTimes.reserve(2);  // one per modulation frequency, at most two
  const hal::CameraStatus r = camera_.register_data_listener(this);
  if (r != hal::CameraStatus::kSuccess) return from_hal(r);
  // As royale: the first use case the camera offers, whatever the camera
  // ran before.
  std::size_t count = 0;
  const hal::UseCase* all = hal::use_cases(&count);
  if (count > 0) {
    const hal::CameraStatus u = camera_.set_use_case(all[0].name);
    if (u != hal::CameraStatus::kSuccess) return from_hal(u);
  }
  initialized_ = true;
  return royale::CameraStatus::SUCCESS;
}

royale::CameraStatus PicoFlexxDevice::getId(royale::String& id) const {
  id = id_;
  return royale::CameraStatus::SUCCESS;
}

royale::CameraStatus PicoFlexxDevice::getCameraName(royale::String& cameraName) const {
  cameraName = "PICOFLEXX";
  return royale::CameraStatus::SUCCESS;
}

royale::CameraStatus PicoFlexxDevice::setUseCase(const royale::String& name) {
  if (!initialized_) return royale::CameraStatus::DEVICE_NOT_INITIALIZED;
  const hal::CameraStatus s = camera_.set_use_case(name.c_str());
  if (s == hal::CameraStatus::kSuccess) {
    // A new use case runs at its own rate.
    std::lock_guard<std::mutex> lock(listener_mutex_);
    set_rate_hz_ = 0;
    next_due_us_ = -1;
  }
  return from_hal(s);
}

royale::CameraStatus PicoFlexxDevice::getUseCases(royale::Vector<royale::String>& useCases) const {
  if (!initialized_) return royale::CameraStatus::DEVICE_NOT_INITIALIZED;
  std::size_t count = 0;
  const hal::UseCase* all = hal::use_cases(&count);
  useCases.clear();
  for (std::size_t i = 0; i < count; ++i) useCases.push_back(all[i].name);
  return royale::CameraStatus::SUCCESS;
}

royale::CameraStatus PicoFlexxDevice::getCameraInfo(
    royale::Vector<royale::Pair<royale::String, royale::String>>& camInfo) const {
  if (!initialized_) return royale::CameraStatus::DEVICE_NOT_INITIALIZED;
  const pico_flexx::Identity& who = camera_.usb().identity();
  camInfo.clear();
  camInfo.push_back({"SERIAL_NUMBER", who.serial});
  camInfo.push_back({"FIRMWARE_VERSION", std::to_string(who.firmware_major) + "." +
                                             std::to_string(who.firmware_minor)});
  camInfo.push_back({"USB_PROTOCOL_VERSION", std::to_string(who.protocol_version)});
  return royale::CameraStatus::SUCCESS;
}

royale::CameraStatus PicoFlexxDevice::getStreams(royale::Vector<royale::StreamId>& streams) const {
  if (!initialized_) return royale::CameraStatus::DEVICE_NOT_INITIALIZED;
  streams.assign(1, kStream);
  return royale::CameraStatus::SUCCESS;
}

royale::CameraStatus PicoFlexxDevice::getNumberOfStreams(const royale::String& name,
                                                         uint32_t& nrStreams) const {
  std::size_t count = 0;
  const hal::UseCase* all = hal::use_cases(&count);
  for (std::size_t i = 0; i < count; ++i) {
    if (name == all[i].name) {
      nrStreams = 1;
      return royale::CameraStatus::SUCCESS;
    }
  }
  return royale::CameraStatus::USECASE_NOT_SUPPORTED;
}

royale::CameraStatus PicoFlexxDevice::getCurrentUseCase(royale::String& useCase) const {
  if (!initialized_) return royale::CameraStatus::DEVICE_NOT_INITIALIZED;
  const hal::UseCase* current = nullptr;
  const hal::CameraStatus s = camera_.current_use_case(&current);
  if (s != hal::CameraStatus::kSuccess) return from_hal(s);
  useCase = current->name;
  return royale::CameraStatus::SUCCESS;
}

royale::CameraStatus PicoFlexxDevice::setFrameRate(uint16_t framerate) {
  if (!initialized_) return royale::CameraStatus::DEVICE_NOT_INITIALIZED;
  const hal::UseCase* current = nullptr;
  const hal::CameraStatus s = camera_.current_use_case(&current);
  if (s != hal::CameraStatus::kSuccess) return from_hal(s);
  if (framerate == 0 || framerate > current->frame_rate_hz) {
    return royale::CameraStatus::FRAMERATE_NOT_SUPPORTED;
  }
  std::lock_guard<std::mutex> lock(listener_mutex_);
  set_rate_hz_ = framerate == current->frame_rate_hz ? 0 : framerate;
  camera_rate_hz_ = static_cast<uint16_t>(current->frame_rate_hz);
  next_due_us_ = -1;
  return royale::CameraStatus::SUCCESS;
}

royale::CameraStatus PicoFlexxDevice::getFrameRate(uint16_t& frameRate) const {
  if (!initialized_) return royale::CameraStatus::DEVICE_NOT_INITIALIZED;
  const hal::UseCase* current = nullptr;
  const hal::CameraStatus s = camera_.current_use_case(&current);
  if (s != hal::CameraStatus::kSuccess) return from_hal(s);
  std::lock_guard<std::mutex> lock(listener_mutex_);
  frameRate = set_rate_hz_ != 0 ? set_rate_hz_ : static_cast<uint16_t>(current->frame_rate_hz);
  return royale::CameraStatus::SUCCESS;
}

royale::CameraStatus PicoFlexxDevice::getMaxFrameRate(uint16_t& maxFrameRate) const {
  if (!initialized_) return royale::CameraStatus::DEVICE_NOT_INITIALIZED;
  const hal::UseCase* current = nullptr;
  const hal::CameraStatus s = camera_.current_use_case(&current);
  if (s != hal::CameraStatus::kSuccess) return from_hal(s);
  maxFrameRate = static_cast<uint16_t>(current->frame_rate_hz);
  return royale::CameraStatus::SUCCESS;
}

royale::CameraStatus PicoFlexxDevice::setExposureTime(uint32_t exposureTime,
                                                      royale::StreamId streamId) {
  if (!initialized_) return royale::CameraStatus::DEVICE_NOT_INITIALIZED;
  if (!names_the_stream(streamId)) return royale::CameraStatus::INVALID_VALUE;
  // The camera refuses it while automatic: EXPOSURE_MODE_INVALID, as royale.
  return from_hal(camera_.set_exposure_time(exposureTime));
}

royale::CameraStatus PicoFlexxDevice::setExposureMode(royale::ExposureMode exposureMode,
                                                      royale::StreamId streamId) {
  if (!initialized_) return royale::CameraStatus::DEVICE_NOT_INITIALIZED;
  if (!names_the_stream(streamId)) return royale::CameraStatus::INVALID_VALUE;
  const hal::ExposureMode mode = exposureMode == royale::ExposureMode::AUTOMATIC
                                     ? hal::ExposureMode::kAutomatic
                                     : hal::ExposureMode::kManual;
  const hal::CameraStatus s = camera_.set_exposure_mode(mode);
  if (s == hal::CameraStatus::kSuccess) exposure_mode_ = exposureMode;
  return from_hal(s);
}

royale::CameraStatus PicoFlexxDevice::getExposureMode(royale::ExposureMode& exposureMode,
                                                      royale::StreamId streamId) const {
  if (!initialized_) return royale::CameraStatus::DEVICE_NOT_INITIALIZED;
  if (!names_the_stream(streamId)) return royale::CameraStatus::INVALID_VALUE;
  exposureMode = exposure_mode_;
  return royale::CameraStatus::SUCCESS;
}

royale::CameraStatus PicoFlexxDevice::getExposureLimits(
    royale::Pair<uint32_t, uint32_t>& exposureLimits, royale::StreamId streamId) const {
  if (!initialized_) return royale::CameraStatus::DEVICE_NOT_INITIALIZED;
  if (!names_the_stream(streamId)) return royale::CameraStatus::INVALID_VALUE;
  const hal::UseCase* current = nullptr;
  const hal::CameraStatus s = camera_.current_use_case(&current);
  if (s != hal::CameraStatus::kSuccess) return from_hal(s);
  // PROTOCOL.md, SET_EXPOSURE_TIME: 1 us .. the use case's longest.
  exposureLimits = {1u, current->max_exposure_us};
  return royale::CameraStatus::SUCCESS;
}

royale::CameraStatus PicoFlexxDevice::setExposureTimes(const royale::Vector<uint32_t>&,
                                                       royale::StreamId) {
  if (!initialized_) return royale::CameraStatus::DEVICE_NOT_INITIALIZED;
  return royale::CameraStatus::INSUFFICIENT_PRIVILEGES;  // level 2
}

royale::CameraStatus PicoFlexxDevice::registerDataListener(royale::IDepthDataListener* listener) {
  if (listener == nullptr) return royale::CameraStatus::INVALID_VALUE;
  std::lock_guard<std::mutex> lock(listener_mutex_);
  listener_ = listener;
  return royale::CameraStatus::SUCCESS;
}

royale::CameraStatus PicoFlexxDevice::unregisterDataListener() {
  std::lock_guard<std::mutex> lock(listener_mutex_);
  listener_ = nullptr;
  return royale::CameraStatus::SUCCESS;
}

royale::CameraStatus PicoFlexxDevice::registerEventListener(royale::IEventListener* listener) {
  if (listener == nullptr) return royale::CameraStatus::INVALID_VALUE;
  {
    std::lock_guard<std::mutex> lock(event_mutex_);
    event_listener_ = listener;
  }
  if (!watching_.exchange(true)) watcher_ = std::thread([this] { watch_for_events(); });
  return royale::CameraStatus::SUCCESS;
}

royale::CameraStatus PicoFlexxDevice::unregisterEventListener() {
  std::unique_lock<std::mutex> lock(event_mutex_);
  event_listener_ = nullptr;
  // Once this returns the listener is not called again: wait for a call in
  // progress, unless this is that call (the listener unregistering itself).
  if (std::this_thread::get_id() != watcher_.get_id()) {
    event_idle_.wait(lock, [this] { return !in_event_callback_; });
  }
  return royale::CameraStatus::SUCCESS;
}

namespace {

// One of the device's events: its severity, type and words.
class DeviceEvent final : public royale::IEvent {
 public:
  DeviceEvent(royale::EventSeverity severity, royale::EventType type, const char* text)
      : severity_(severity), type_(type), text_(text) {}
  royale::EventSeverity severity() const override { return severity_; }
  const royale::String describe() const override { return text_; }
  royale::EventType type() const override { return type_; }

 private:
  royale::EventSeverity severity_;
  royale::EventType type_;
  royale::String text_;
};

}  // namespace

void PicoFlexxDevice::emit(royale::EventSeverity severity, royale::EventType type,
                           const char* text) {
  royale::IEventListener* listener = nullptr;
  {
    std::lock_guard<std::mutex> lock(event_mutex_);
    listener = event_listener_;
    in_event_callback_ = listener != nullptr;
  }
  if (listener == nullptr) return;
  // Called without the lock: the listener may register or unregister
  // itself, or take locks of its own that its other threads hold while
  // unregistering.
  listener->onEvent(std::make_unique<DeviceEvent>(severity, type, text));
  {
    std::lock_guard<std::mutex> lock(event_mutex_);
    in_event_callback_ = false;
  }
  event_idle_.notify_all();
}

void PicoFlexxDevice::watch_for_events() {
  while (watching_.load()) {
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    const pico_flexx::CameraState state = camera_.usb().state();
    if (state == pico_flexx::CameraState::kLost && !reported_lost_) {
      reported_lost_ = true;
      char text[128];
      std::snprintf(text, sizeof text, "the camera is lost (%s)",
                    pico_flexx::to_string(camera_.usb().lost_reason()));
      emit(royale::EventSeverity::ROYALE_FATAL, royale::EventType::ROYALE_DEVICE_DISCONNECTED,
           text);
    } else if (state != pico_flexx::CameraState::kLost) {
      reported_lost_ = false;  // re-acquired: a later loss is news again
    }
    report_stream_stats(clock_.now_us());
  }
}

void PicoFlexxDevice::report_stream_stats(std::int64_t now_us) {
  if (!camera_.is_capturing()) {
    last_stats_us_ = 0;
    return;
  }
  const pico_flexx::UsbCounters c = camera_.usb().counters();
  // Every frame not handed on leaves a gap in the sequence numbers (the
  // ones the driver refused as well as the ones lost at the camera).
  const std::uint64_t dropped = c.assembly.frames_missed;
  if (last_stats_us_ == 0) {
    last_stats_us_ = now_us;
    last_delivered_ = c.frames_delivered;
    last_dropped_ = dropped;
    return;
  }
  if (now_us - last_stats_us_ < 1000000) return;
  const std::uint64_t delivered_now = c.frames_delivered - last_delivered_;
  const std::uint64_t dropped_now = dropped - last_dropped_;
  // No frame at all while capturing is a dropped second too, though no
  // sequence gap can count it yet (the camera silent, pulled out).
  char text[160];
  std::snprintf(
      text, sizeof text, "%llu frames received and %llu dropped in the last %.1f s (camera %s)",
      static_cast<unsigned long long>(delivered_now), static_cast<unsigned long long>(dropped_now),
      1e-6 * static_cast<double>(now_us - last_stats_us_),
      pico_flexx::to_string(camera_.usb().state()));
  const bool missing = dropped_now > 0 || delivered_now == 0;
  emit(missing ? royale::EventSeverity::ROYALE_WARNING : royale::EventSeverity::ROYALE_INFO,
       royale::EventType::ROYALE_RAW_FRAME_STATS, text);
  last_stats_us_ = now_us;
  last_delivered_ = c.frames_delivered;
  last_dropped_ = dropped;
}

royale::CameraStatus PicoFlexxDevice::startCapture() {
  if (!initialized_) return royale::CameraStatus::DEVICE_NOT_INITIALIZED;
  {
    // royale starts no capture without a listener to take the frames.
    std::lock_guard<std::mutex> lock(listener_mutex_);
    if (listener_ == nullptr) return royale::CameraStatus::LOGIC_ERROR;
  }
  return from_hal(camera_.start_capture());
}

royale::CameraStatus PicoFlexxDevice::stopCapture() {
  if (!camera_.is_capturing()) return royale::CameraStatus::SUCCESS;
  return from_hal(camera_.stop_capture());
}

royale::CameraStatus PicoFlexxDevice::getMaxSensorWidth(uint16_t& maxSensorWidth) const {
  maxSensorWidth = static_cast<uint16_t>(tof::kWidthPx);
  return royale::CameraStatus::SUCCESS;
}

royale::CameraStatus PicoFlexxDevice::getMaxSensorHeight(uint16_t& maxSensorHeight) const {
  maxSensorHeight = static_cast<uint16_t>(tof::kHeightPx);
  return royale::CameraStatus::SUCCESS;
}

royale::CameraStatus PicoFlexxDevice::getLensParameters(royale::LensParameters& param) const {
  hal::LensParameters lens;
  const hal::CameraStatus s = camera_.lens_parameters(&lens);
  if (s != hal::CameraStatus::kSuccess) return from_hal(s);
  param.principalPoint = {static_cast<float>(lens.cx_px), static_cast<float>(lens.cy_px)};
  param.focalLength = {static_cast<float>(lens.fx_px), static_cast<float>(lens.fy_px)};
  param.distortionTangential = {static_cast<float>(lens.p1), static_cast<float>(lens.p2)};
  param.distortionRadial = {static_cast<float>(lens.k1), static_cast<float>(lens.k2),
                            static_cast<float>(lens.k3)};
  return royale::CameraStatus::SUCCESS;
}

royale::CameraStatus PicoFlexxDevice::isConnected(bool& connected) const {
  connected = camera_.is_connected();
  return royale::CameraStatus::SUCCESS;
}

royale::CameraStatus PicoFlexxDevice::isCalibrated(bool& calibrated) const {
  // initialize() succeeds only on the camera's own calibration.
  calibrated = initialized_;
  return royale::CameraStatus::SUCCESS;
}

royale::CameraStatus PicoFlexxDevice::isCapturing(bool& capturing) const {
  capturing = camera_.is_capturing();
  return royale::CameraStatus::SUCCESS;
}

royale::CameraStatus PicoFlexxDevice::getAccessLevel(royale::CameraAccessLevel& accessLevel) const {
  accessLevel = royale::CameraAccessLevel::L1;
  return royale::CameraStatus::SUCCESS;
}

bool PicoFlexxDevice::due_at_set_rate(std::int64_t capture_us) {
  if (set_rate_hz_ == 0 || camera_rate_hz_ == 0) return true;
  const std::int64_t period_us = 1000000 / set_rate_hz_;
  const std::int64_t slack_us = 500000 / camera_rate_hz_;
  if (next_due_us_ >= 0 && capture_us < next_due_us_ - slack_us) return false;
  // On the rate's own grid, so that the skipped frames do not slow it; a
  // gap (frames lost, capture restarted) starts the grid again.
  const bool on_grid = next_due_us_ >= 0 && capture_us <= next_due_us_ + period_us;
  next_due_us_ = (on_grid ? next_due_us_ : capture_us) + period_us;
  return true;
}

void PicoFlexxDevice::on_new_data(const hal::DepthFrame& frame) {
  std::lock_guard<std::mutex> lock(listener_mutex_);
  if (listener_ == nullptr) return;
  if (!due_at_set_rate(frame.capture_time_us)) return;
  const std::size_t n = static_cast<std::size_t>(frame.width) * frame.height;
  if (n > data_.points.capacity()) return;  // cannot happen: the sensor's size
  // Within the capacities reserved at initialize(): no allocation.
  data_.points.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const hal::DepthPoint& p = frame.points[i];
    royale::DepthPoint& q = data_.points[i];
    q.x = p.x_m;
    q.y = p.y_m;
    q.z = p.z_m;
    q.noise = p.noise_m;
    q.grayValue = p.gray_value;
    q.depthConfidence = p.confidence;
  }
  data_.timeStamp = std::chrono::microseconds(epoch_us_of(frame.capture_time_us, clock_));
  data_.width = static_cast<uint16_t>(frame.width);
  data_.height = static_cast<uint16_t>(frame.height);
  const int frequencies = camera_.delivering_frequencies();
  data_.exposureTimes.resize(frequencies < 1 ? 1 : (frequencies > 2 ? 2 : frequencies));
  for (uint32_t& t : data_.exposureTimes) t = camera_.delivering_exposure_us();
  listener_->onNewData(&data_);
}

}  // namespace royale
