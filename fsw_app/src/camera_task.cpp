#include "fsw_app/camera_task.hpp"

#include <chrono>

namespace fsw_app {

void CameraTask::note_capture_time(std::int64_t capture_time_us) {
  if (last_capture_us_ >= 0 && capture_time_us > last_capture_us_) {
    const std::int64_t gap_us = capture_time_us - last_capture_us_;
    if (gap_us > longest_gap_us_.load()) longest_gap_us_.store(gap_us);
  }
  if (capture_time_us > last_capture_us_) last_capture_us_ = capture_time_us;
}

void CameraTask::on_new_data(const hal::DepthFrame& frame) {
  note_capture_time(frame.capture_time_us);
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
