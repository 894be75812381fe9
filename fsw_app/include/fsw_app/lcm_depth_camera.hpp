#pragma once
// A depth camera whose frames arrive as DEPTH_FRAME messages: from a camera
// task in another process, from lcm-logplayer, or from the in-process log
// player (log_player.hpp). It lets the estimator task run on its own, fed
// over LCM, behind the same interface as the Pico Flexx.
//
// A message that is not a well-formed frame no larger than the buffers
// (max_frame_size) is dropped: the listener gets a frame with no points,
// which the camera task counts as corrupt, and the reason is kept here.
#include <atomic>
#include <cstdint>
#include <memory>

#include "fsw_app/depth_frame_msg.hpp"
#include "fsw_app/lcm_hub.hpp"
#include "hal/depth_camera.hpp"

namespace fsw_app {

class LcmDepthCamera final : public hal::DepthCamera {
 public:
  // Subscribes to `channel` on the hub (before the hub starts).
  LcmDepthCamera(LcmHub& hub, std::uint32_t max_width, std::uint32_t max_height,
                 const char* channel = channel::kDepthFrame);

  [[nodiscard]] hal::CameraStatus initialize() override;
  // The use case only names the expected rate; the sender sets the real one.
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
  bool is_connected() const override { return initialized_; }
  bool is_capturing() const override { return capturing_.load(); }

  // Dispatcher side: one DEPTH_FRAME message.
  void deliver(const void* data, std::uint32_t size, std::int64_t now_us);

  std::uint64_t frames_delivered() const { return delivered_.load(); }
  std::uint64_t messages_rejected() const { return rejected_.load(); }
  // The same verdicts in the terms every checked channel uses.
  const InputCounts& input_counts() const { return counts_; }
  // Why the last rejected message was rejected (kOk when none was).
  FrameMsgStatus last_rejection() const { return last_rejection_.load(); }

 private:
  std::uint32_t max_width_, max_height_;
  bool initialized_ = false;
  const hal::UseCase* use_case_ = nullptr;
  hal::DepthDataListener* listener_ = nullptr;
  std::atomic<bool> capturing_{false};
  hrp::depth_frame_t msg_;
  std::unique_ptr<hal::DepthPoint[]> points_;
  std::atomic<std::uint64_t> delivered_{0}, rejected_{0};
  std::atomic<FrameMsgStatus> last_rejection_{FrameMsgStatus::kOk};
  InputCounts counts_;
};

}  // namespace fsw_app
