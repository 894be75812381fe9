#pragma once
// The camera task: the HAL's depth frames into the fixed ring. It runs on
// the camera's own delivery thread (royale's listener model); a frame that
// cannot be a depth frame (no points, zero or oversize dimensions) is
// dropped and counted, never passed on.
#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <mutex>

#include "fsw_app/frame_ring.hpp"
#include "hal/depth_camera.hpp"

namespace fsw_app {

class CameraTask final : public hal::DepthDataListener {
 public:
  CameraTask(FrameRing& ring, std::uint32_t max_width, std::uint32_t max_height)
      : ring_(ring), max_width_(max_width), max_height_(max_height) {}

  void on_new_data(const hal::DepthFrame& frame) override;

  // Waits up to timeout_ms for a frame pushed after `seen` (a count from
  // received()); returns the new count.
  std::uint64_t wait_for_frame(std::uint64_t seen, int timeout_ms);
  std::uint64_t received() const { return received_.load(); }
  std::uint64_t corrupt() const { return corrupt_.load(); }
  // The longest time between the capture stamps of successive frames
  // (corrupt ones too): a camera pipeline stalled by its host shows here,
  // as a gap of several frame periods.
  std::int64_t longest_gap_us() const { return longest_gap_us_.load(); }

 private:
  void note_capture_time(std::int64_t capture_time_us);

  FrameRing& ring_;
  std::uint32_t max_width_, max_height_;
  std::atomic<std::uint64_t> received_{0}, corrupt_{0};
  std::int64_t last_capture_us_ = -1;  // only the delivery thread touches it
  std::atomic<std::int64_t> longest_gap_us_{0};
  std::mutex mutex_;
  std::condition_variable cv_;
};

}  // namespace fsw_app
