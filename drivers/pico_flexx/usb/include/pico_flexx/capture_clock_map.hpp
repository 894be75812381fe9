#pragma once
// A camera's capture time stamps on the host's monotonic clock.
//
// The Pico Flexx stamps each frame's header with its capture time on its
// own clock (PROTOCOL.md), and royale stamps each DepthData with a time
// whose base is the SDK's (the project's royale: the system clock; the
// vendor's: not documented). The estimator wants every time on hal's
// monotonic clock.
//
// A stamp that lies within `same_clock_window_us` before its arrival is
// taken as it is (same clock; a negative window never takes a stamp so, as
// the USB driver knows its stamps are the camera's). Otherwise the stamp is
// moved by an offset: the least (arrival - stamp) seen over the last one to
// two windows of `window_us`, since a frame can only arrive after it was
// captured, so the least delay is the best bound on the offset. The bound
// is late by the least latency from capture to arrival (for the USB driver,
// which stamps a frame's arrival with its first transfer, the camera's
// readout into its first transfer); the two clocks' drift moves it, which
// the window follows (the bound of each window is its own), and
// `window_change_us` reports: the last closed window's least delay less the
// one before, the mapping's wander over a window. A stamp that then lands
// more than `max_jump_us` off its arrival (the other clock stepped: NTP, a
// camera reset) starts the offset afresh; each restart is counted. A
// smaller step shows as a quicker frame (a tighter bound at once) or ages
// out of the windows within two of them. Pure,
// fixed memory.
#include <cstdint>

namespace pico_flexx {

// The windows are wider than a camera's FIFO holds frames (45 frames: 9 s
// at 5 fps), so that a frame that waited there is neither taken for
// another clock nor for a step of it.
struct CaptureClockMapConfig {
  std::int64_t same_clock_window_us = 10000000;  // a stamp up to 10 s old is on our clock
  std::int64_t max_jump_us = 10000000;           // a mapped stamp this far off arrival: re-anchor
  std::int64_t window_us = 1000000;              // the least delay is the last 1 to 2 windows'
};

enum class CaptureClock : std::uint8_t {
  kUnknown,  // no frame yet
  kSame,     // the stamps are on the host's monotonic clock
  kMapped,   // the stamps are on another clock, moved by an offset
};
const char* to_string(CaptureClock c);

class CaptureClockMap {
 public:
  explicit CaptureClockMap(const CaptureClockMapConfig& cfg = {}) : cfg_(cfg) {}

  // The capture time on the host's clock of a frame stamped `stamp_us` and
  // received at `arrival_us` (host clock). Never after the arrival.
  std::int64_t to_host_us(std::int64_t stamp_us, std::int64_t arrival_us);

  CaptureClock clock() const { return clock_; }
  std::int64_t offset_us() const { return offset_us_; }
  std::uint32_t reanchors() const { return reanchors_; }
  // The last closed window's least delay less the one before it (0 until
  // two windows have closed).
  std::int64_t window_change_us() const { return window_change_us_; }
  void reset();

 private:
  void start_afresh(std::int64_t delay_us, std::int64_t arrival_us);
  void note_delay(std::int64_t delay_us, std::int64_t arrival_us);

  CaptureClockMapConfig cfg_;
  CaptureClock clock_ = CaptureClock::kUnknown;
  std::int64_t offset_us_ = 0;
  std::uint32_t reanchors_ = 0;
  // The least delay of the window in progress and of the one before it.
  std::int64_t window_start_us_ = 0;
  std::int64_t window_least_us_ = 0;
  std::int64_t previous_least_us_ = 0;
  bool have_previous_ = false;
  std::int64_t window_change_us_ = 0;
};

}  // namespace pico_flexx
