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
  const std::uint32_t reanchors = reanchors_;
  *this = CaptureClockMap(cfg_);
  reanchors_ = reanchors;
}

void CaptureClockMap::start_afresh(std::int64_t delay_us, std::int64_t arrival_us) {
  offset_us_ = delay_us;
  window_start_us_ = arrival_us;
  window_least_us_ = delay_us;
  have_previous_ = false;
  window_change_us_ = 0;
}

void CaptureClockMap::note_delay(std::int64_t delay_us, std::int64_t arrival_us) {
  if (arrival_us - window_start_us_ >= cfg_.window_us) {
    // The window closes: its least delay becomes the one before, and the
    // bound is the new window's and that one's.
    if (have_previous_) window_change_us_ = window_least_us_ - previous_least_us_;
    previous_least_us_ = window_least_us_;
    have_previous_ = true;
    window_start_us_ = arrival_us;
    window_least_us_ = delay_us;
  } else if (delay_us < window_least_us_) {
    window_least_us_ = delay_us;
  }
  offset_us_ = have_previous_ && previous_least_us_ < window_least_us_ ? previous_least_us_
                                                                       : window_least_us_;
}

std::int64_t CaptureClockMap::to_host_us(std::int64_t stamp_us, std::int64_t arrival_us) {
  const std::int64_t delay_us = arrival_us - stamp_us;
  const bool on_our_clock = delay_us >= 0 && delay_us <= cfg_.same_clock_window_us;
  if (clock_ == CaptureClock::kUnknown) {
    clock_ = on_our_clock ? CaptureClock::kSame : CaptureClock::kMapped;
    if (on_our_clock) {
      offset_us_ = 0;
    } else {
      start_afresh(delay_us, arrival_us);
    }
  } else if (clock_ == CaptureClock::kSame && !on_our_clock) {
    // The stamps left our clock's window: another time base after all.
    clock_ = CaptureClock::kMapped;
    start_afresh(delay_us, arrival_us);
    ++reanchors_;
  } else if (clock_ == CaptureClock::kMapped) {
    const std::int64_t off_us = delay_us - offset_us_;  // the frame's delay beyond the least
    if (off_us < -cfg_.max_jump_us || off_us > cfg_.max_jump_us) {
      // The other clock stepped forward (a frame far quicker than any) or
      // back (far slower): what was learned of the offset is void.
      start_afresh(delay_us, arrival_us);
      ++reanchors_;
    } else {
      note_delay(delay_us, arrival_us);
    }
  }
  const std::int64_t host_us = stamp_us + offset_us_;
  return host_us > arrival_us ? arrival_us : host_us;
}

}  // namespace pico_flexx
