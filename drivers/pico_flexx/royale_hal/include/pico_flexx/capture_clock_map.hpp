#pragma once
// A camera's capture time stamps on the host's monotonic clock.
//
// royale stamps each DepthData with a capture time whose time base is the
// SDK's: the project's royale uses the host's monotonic clock, the vendor's
// may use another (the system clock, or the camera's own counter). The
// estimator wants every time on hal's monotonic clock. A stamp that already
// lies within `same_clock_window_us` before the arrival time is taken as it
// is (same clock). Otherwise the stamp is moved by an offset: the smallest
// (arrival - stamp) seen, since a frame can only arrive after it was
// captured, so the least delay seen is the best bound on the offset. A
// stamp that then lands more than `max_jump_us` off its arrival (the
// other clock stepped: NTP, a camera reset) starts the offset afresh; each
// restart is counted. Pure, fixed memory.
#include <cstdint>

namespace pico_flexx {

struct CaptureClockMapConfig {
  std::int64_t same_clock_window_us = 1000000;  // a stamp up to 1 s old is on our clock
  std::int64_t max_jump_us = 1000000;           // a mapped stamp this far off arrival: re-anchor
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
  void reset();

 private:
  CaptureClockMapConfig cfg_;
  CaptureClock clock_ = CaptureClock::kUnknown;
  std::int64_t offset_us_ = 0;
  std::uint32_t reanchors_ = 0;
};

}  // namespace pico_flexx
