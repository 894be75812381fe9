#pragma once
// Time is injected: flight code asks a Clock, tests hand it a manual one.
#include <cstdint>

namespace hal {

class Clock {
 public:
  virtual ~Clock() = default;
  // Microseconds on a monotonic time base (never jumps with wall-clock time).
  virtual std::int64_t now_us() const = 0;
};

// CLOCK_MONOTONIC.
class MonotonicClock final : public Clock {
 public:
  std::int64_t now_us() const override;
};

// A clock that moves only when told to; for tests and simulation.
class ManualClock final : public Clock {
 public:
  explicit ManualClock(std::int64_t start_us = 0) : now_us_(start_us) {}
  std::int64_t now_us() const override { return now_us_; }
  void advance_us(std::int64_t dt_us) { now_us_ += dt_us; }
  void set_us(std::int64_t t_us) { now_us_ = t_us; }

 private:
  std::int64_t now_us_;
};

// The system (wall) clock's reading since the 1970 epoch less `clock`'s,
// both read now, in microseconds: what moves a time on `clock` to epoch
// time (add it) or back (subtract it). Exact while no one steps the system
// clock between the stamp and the reading.
std::int64_t system_minus_clock_us(const Clock& clock);

}  // namespace hal
