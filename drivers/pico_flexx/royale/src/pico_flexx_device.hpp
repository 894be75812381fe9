#pragma once
// royale::ICameraDevice on the project's Pico Flexx driver: the USB driver
// and the robot's ToF processing behind hal::DepthCamera
// (pico_flexx::UsbDepthCamera), its depth frames copied into one
// royale::DepthData sized at initialize(), so that nothing is allocated
// per frame.
#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <thread>

#include "hal/clock.hpp"
#include "hal/depth_camera.hpp"
#include "pico_flexx/usb_depth_camera.hpp"
#include "royale/ICameraDevice.hpp"

namespace royale {

class PicoFlexxDevice final : public ICameraDevice, private hal::DepthDataListener {
 public:
  PicoFlexxDevice(const pico_flexx::UsbCameraConfig& usb, const royale::String& id);
  ~PicoFlexxDevice() override;
  PicoFlexxDevice(const PicoFlexxDevice&) = delete;
  PicoFlexxDevice& operator=(const PicoFlexxDevice&) = delete;

  royale::CameraStatus initialize() override;
  royale::CameraStatus getId(royale::String& id) const override;
  royale::CameraStatus getCameraName(royale::String& cameraName) const override;
  royale::CameraStatus setUseCase(const royale::String& name) override;
  royale::CameraStatus getUseCases(royale::Vector<royale::String>& useCases) const override;
  royale::CameraStatus getCurrentUseCase(royale::String& useCase) const override;
  royale::CameraStatus getCameraInfo(
      royale::Vector<royale::Pair<royale::String, royale::String>>& camInfo) const override;
  royale::CameraStatus getStreams(royale::Vector<royale::StreamId>& streams) const override;
  royale::CameraStatus getNumberOfStreams(const royale::String& name,
                                          uint32_t& nrStreams) const override;
  royale::CameraStatus setFrameRate(uint16_t framerate) override;
  royale::CameraStatus getFrameRate(uint16_t& frameRate) const override;
  royale::CameraStatus getMaxFrameRate(uint16_t& maxFrameRate) const override;
  royale::CameraStatus setExposureTime(uint32_t exposureTime, royale::StreamId streamId) override;
  royale::CameraStatus setExposureMode(royale::ExposureMode exposureMode,
                                       royale::StreamId streamId) override;
  royale::CameraStatus getExposureMode(royale::ExposureMode& exposureMode,
                                       royale::StreamId streamId) const override;
  royale::CameraStatus getExposureLimits(royale::Pair<uint32_t, uint32_t>& exposureLimits,
                                         royale::StreamId streamId) const override;
  royale::CameraStatus setExposureTimes(const royale::Vector<uint32_t>& exposureTimes,
                                        royale::StreamId streamId) override;
  royale::CameraStatus registerDataListener(royale::IDepthDataListener* listener) override;
  royale::CameraStatus unregisterDataListener() override;
  royale::CameraStatus registerEventListener(royale::IEventListener* listener) override;
  royale::CameraStatus unregisterEventListener() override;
  royale::CameraStatus startCapture() override;
  royale::CameraStatus stopCapture() override;
  royale::CameraStatus getMaxSensorWidth(uint16_t& maxSensorWidth) const override;
  royale::CameraStatus getMaxSensorHeight(uint16_t& maxSensorHeight) const override;
  royale::CameraStatus getLensParameters(royale::LensParameters& param) const override;
  royale::CameraStatus isConnected(bool& connected) const override;
  royale::CameraStatus isCalibrated(bool& calibrated) const override;
  royale::CameraStatus isCapturing(bool& capturing) const override;
  royale::CameraStatus getAccessLevel(royale::CameraAccessLevel& accessLevel) const override;

 private:
  // The driver's frame, on its event thread.
  void on_new_data(const hal::DepthFrame& frame) override;
  // Whether a frame captured then falls due at the rate set (under
  // listener_mutex_): one each 1/rate, within half the camera's own frame
  // period; after a gap longer than that the count starts again.
  bool due_at_set_rate(std::int64_t capture_us);
  // The event thread's loop: every 100 ms, the camera's state (a lost
  // camera is reported once), and each second of capture the USB stream's
  // frames delivered and dropped since the last report.
  void watch_for_events();
  void report_stream_stats(std::int64_t now_us);
  void emit(royale::EventSeverity severity, royale::EventType type, const char* text);

  // Declared before camera_ so that they outlive its event thread.
  hal::MonotonicClock clock_;
  royale::String id_;
  bool initialized_ = false;
  royale::ExposureMode exposure_mode_ = royale::ExposureMode::MANUAL;
  mutable std::mutex listener_mutex_;  // a listener unregistered is not called again
  royale::IDepthDataListener* listener_ = nullptr;
  // setFrameRate's rate (0: the use case's own), the camera's, and when the
  // next frame falls due (-1: the next frame). Under listener_mutex_.
  uint16_t set_rate_hz_ = 0;
  uint16_t camera_rate_hz_ = 0;
  std::int64_t next_due_us_ = -1;
  royale::DepthData data_{};
  pico_flexx::UsbDepthCamera camera_;
  // Events: the listener, and the thread that finds what to report
  // (started by the first registration, joined by the destructor; so a
  // listener must not destroy the device from its own call).
  std::mutex event_mutex_;
  std::condition_variable event_idle_;  // no call to the listener in progress
  royale::IEventListener* event_listener_ = nullptr;
  bool in_event_callback_ = false;
  std::atomic<bool> watching_{false};
  std::thread watcher_;
  bool reported_lost_ = false;
  std::int64_t last_stats_us_ = 0;
  std::uint64_t last_delivered_ = 0, last_dropped_ = 0;
};

}  // namespace royale
