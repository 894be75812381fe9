#include "fsw_app/frame_ring.hpp"

#include <algorithm>

namespace fsw_app {

const char* to_string(RingStatus status) {
  switch (status) {
    case RingStatus::kOk:
      return "OK";
    case RingStatus::kEmpty:
      return "EMPTY";
    case RingStatus::kFrameTooLarge:
      return "FRAME_TOO_LARGE";
  }
  return "UNKNOWN";
}

FrameRing::FrameRing(std::size_t slots, std::uint32_t max_width, std::uint32_t max_height)
    : n_slots_(slots ? slots : 1),
      max_pixels_(static_cast<std::size_t>(max_width) * max_height),
      slots_(new Slot[n_slots_]),
      storage_(new hal::DepthPoint[n_slots_ * max_pixels_]) {}

RingStatus FrameRing::push(const hal::DepthFrame& frame) {
  const std::size_t n = static_cast<std::size_t>(frame.width) * frame.height;
  if (n > max_pixels_) return RingStatus::kFrameTooLarge;
  std::lock_guard<std::mutex> lock(mutex_);
  const std::uint64_t seq = next_sequence_++;
  Slot& slot = slots_[seq % n_slots_];
  // Overwriting a frame nobody read is a drop.
  if (slot.sequence > last_read_) ++dropped_;
  hal::DepthPoint* dst = &storage_[(seq % n_slots_) * max_pixels_];
  std::copy(frame.points, frame.points + n, dst);
  slot.header = frame;
  slot.header.points = dst;
  slot.sequence = seq;
  return RingStatus::kOk;
}

const FrameRing::Slot* FrameRing::take_newest() {
  const std::uint64_t newest = next_sequence_ - 1;
  if (newest == 0 || newest <= last_read_) return nullptr;
  // Unread frames older than the newest are skipped: dropped.
  const std::uint64_t oldest_kept = newest >= n_slots_ ? newest - n_slots_ + 1 : 1;
  const std::uint64_t first_unread = std::max(last_read_ + 1, oldest_kept);
  dropped_ += newest - first_unread;
  last_read_ = newest;
  return &slots_[newest % n_slots_];
}

std::uint64_t FrameRing::pushed() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return next_sequence_ - 1;
}

std::uint64_t FrameRing::dropped() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return dropped_;
}

}  // namespace fsw_app
