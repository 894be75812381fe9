#pragma once
// Puts each depth frame on DEPTH_FRAME as it passes from the camera to the
// camera task: for an estimator in another process, and for recording a
// run whose frames can be replayed into the estimator later. It sits
// between the camera and its listener, which gets every frame first.
// The message and its encoding buffer are sized once for the largest
// frame; a frame that cannot be a depth frame is passed on, not published.
#include <atomic>
#include <cstdint>

#include "fsw_app/depth_frame_msg.hpp"
#include "fsw_app/lcm_hub.hpp"
#include "hal/clock.hpp"
#include "hal/depth_camera.hpp"

namespace fsw_app {

class FramePublisher final : public hal::DepthDataListener {
 public:
  FramePublisher(LcmHub& hub, const hal::Clock& clock, std::uint32_t max_width,
                 std::uint32_t max_height, hal::DepthDataListener& next);

  void on_new_data(const hal::DepthFrame& frame) override;

  std::uint64_t published() const { return published_.load(); }
  std::uint64_t failures() const { return failures_.load(); }

 private:
  const hal::Clock& clock_;
  std::uint32_t max_width_, max_height_;
  hal::DepthDataListener& next_;
  hrp::depth_frame_t msg_;
  Publisher<hrp::depth_frame_t> publisher_;
  std::atomic<std::uint64_t> published_{0}, failures_{0};
};

}  // namespace fsw_app
