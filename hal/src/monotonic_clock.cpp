#include <chrono>
#include <ctime>

#include "hal/clock.hpp"

namespace hal {

std::int64_t MonotonicClock::now_us() const {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<std::int64_t>(ts.tv_sec) * 1000000 + ts.tv_nsec / 1000;
}

std::int64_t system_minus_clock_us(const Clock& clock) {
  const std::int64_t system_now_us = std::chrono::duration_cast<std::chrono::microseconds>(
                                         std::chrono::system_clock::now().time_since_epoch())
                                         .count();
  return system_now_us - clock.now_us();
}

}  // namespace hal
