#pragma once
// The camera task's fixed ring of frame buffers. Frames are copied in as the
// camera delivers them; the estimator takes the newest. When the estimator
// falls behind, the oldest frames are overwritten (dropped and counted)
// rather than queued: a late pose is worth less than a fresh one.
// Single producer, single consumer, one mutex; buffers sized once.
#include <cstddef>
#include <cstdint>
#include <memory>
#include <mutex>
#include <type_traits>

#include "hal/depth_frame.hpp"

namespace fsw_app {

enum class RingStatus : std::uint8_t { kOk, kEmpty, kFrameTooLarge };
const char* to_string(RingStatus status);

class FrameRing {
 public:
  FrameRing(std::size_t slots, std::uint32_t max_width, std::uint32_t max_height);

  // Copies the frame in; never blocks on the consumer, never allocates.
  RingStatus push(const hal::DepthFrame& frame);

  // Copies the newest unread frame into `out_points` (capacity max pixels)
  // and fills `out`; older unread frames are counted as dropped.
  RingStatus pop_newest(hal::DepthFrame* out, hal::DepthPoint* out_points) {
    return pop_newest_as(out, out_points, [](const hal::DepthPoint& p) { return p; });
  }
  // The same, converting each point as it is copied out (the estimator's
  // own point type): one copy from the ring to the consumer, not two.
  // `out->points` is left null when Point is not hal::DepthPoint.
  template <typename Point, typename Convert>
  RingStatus pop_newest_as(hal::DepthFrame* out, Point* out_points, Convert convert) {
    std::lock_guard<std::mutex> lock(mutex_);
    const Slot* slot = take_newest();
    if (!slot) return RingStatus::kEmpty;
    const std::size_t n = static_cast<std::size_t>(slot->header.width) * slot->header.height;
    for (std::size_t k = 0; k < n; ++k) out_points[k] = convert(slot->header.points[k]);
    *out = slot->header;
    if constexpr (std::is_same_v<Point, hal::DepthPoint>) {
      out->points = out_points;
    } else {
      out->points = nullptr;
    }
    return RingStatus::kOk;
  }

  std::uint64_t pushed() const;
  std::uint64_t dropped() const;

 private:
  struct Slot {
    hal::DepthFrame header;
    std::uint64_t sequence = 0;
  };
  // With the mutex held: the newest unread slot, marked read, with the
  // unread ones before it counted as dropped; null when there is none.
  const Slot* take_newest();
  std::size_t n_slots_;
  std::size_t max_pixels_;
  std::unique_ptr<Slot[]> slots_;
  std::unique_ptr<hal::DepthPoint[]> storage_;
  mutable std::mutex mutex_;
  std::uint64_t next_sequence_ = 1;
  std::uint64_t last_read_ = 0;
  std::uint64_t dropped_ = 0;
};

}  // namespace fsw_app
