#include "fsw_app/camera_task.hpp"

#include <chrono>

namespace fsw_app {

void CameraTask::on_new_data(const hal::DepthFrame& frame) {
  if (frame.points == nullptr || frame.width == 0 || frame.height == 0 ||
      frame.width > max_width_ || frame.height > max_height_ ||
      ring_.push(frame) != RingStatus::kOk) {
    corrupt_.fetch_add(1);
    return;
  }
  {
    std::lock_guard<std::mutex> lock(mutex_);
    received_.fetch_add(1);
  }
  cv_.notify_one();
}

std::uint64_t CameraTask::wait_for_frame(std::uint64_t seen, int timeout_ms) {
  std::unique_lock<std::mutex> lock(mutex_);
  cv_.wait_for(lock, std::chrono::milliseconds(timeout_ms),
               [&] { return received_.load() > seen; });
  return received_.load();
}

}  // namespace fsw_app
