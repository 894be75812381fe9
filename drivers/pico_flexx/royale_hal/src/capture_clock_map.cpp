#include "pico_flexx/capture_clock_map.hpp"

namespace pico_flexx {

const char* to_string(CaptureClock c) {
  switch (c) {
    case CaptureClock::kUnknown:
      return "UNKNOWN";
    case CaptureClock::kSame:
      return "SAME";
    case CaptureClock::kMapped:
      return "MAPPED";
  }
  return "UNKNOWN";
}

void CaptureClockMap::reset() {
  clock_ = CaptureClock::kUnknown;
  offset_us_ = 0;
}

std::int64_t CaptureClockMap::to_host_us(std::int64_t stamp_us, std::int64_t arrival_us) {
  const std::int64_t delay_us = arrival_us - stamp_us;
  const bool on_our_clock = delay_us >= 0 && delay_us <= cfg_.same_clock_window_us;
  if (clock_ == CaptureClock::kUnknown) {
    clock_ = on_our_clock ? CaptureClock::kSame : CaptureClock::kMapped;
    offset_us_ = on_our_clock ? 0 : delay_us;
  } else if (clock_ == CaptureClock::kSame && !on_our_clock) {
    // The stamps left our clock's window: another time base after all.
    clock_ = CaptureClock::kMapped;
    offset_us_ = delay_us;
    ++reanchors_;
  } else if (clock_ == CaptureClock::kMapped) {
    const std::int64_t off_us = delay_us - offset_us_;  // the frame's delay beyond the least
    if (off_us < 0) {
      // A frame that came quicker: a tighter bound, or (by far) the other
      // clock stepped forward.
      if (off_us < -cfg_.max_jump_us) ++reanchors_;
      offset_us_ = delay_us;
    } else if (off_us > cfg_.max_jump_us) {
      offset_us_ = delay_us;  // the other clock stepped back
      ++reanchors_;
    }
  }
  const std::int64_t host_us = stamp_us + offset_us_;
  return host_us > arrival_us ? arrival_us : host_us;
}

}  // namespace pico_flexx
