#pragma once
// A thread that calls a function at a fixed period until stopped. An
// overrun does not queue a burst of catch-up calls: the schedule restarts
// from now. The function is stored once, at start. The thread may ask for
// real-time scheduling, and it keeps the figures that tell whether it ran
// on time: cycles, overruns, the longest gap between two cycle starts.
#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <thread>
#include <utility>

#include "hal/realtime.hpp"

namespace fsw_app {

struct CycleStats {
  std::int64_t cycles = 0;
  std::int64_t overruns = 0;  // cycles that ended after the next one was due
  std::int64_t longest_gap_us = 0;
  std::int64_t longest_cycle_us = 0;  // the function's own longest run
  hal::RealtimeStatus realtime = hal::RealtimeStatus::kNotRequested;
};

class PeriodicThread {
 public:
  PeriodicThread() = default;
  PeriodicThread(const PeriodicThread&) = delete;
  PeriodicThread& operator=(const PeriodicThread&) = delete;
  ~PeriodicThread() { stop(); }

  // rt_priority 0: the normal scheduler; 1..99: SCHED_FIFO if permitted.
  void start(std::int64_t period_us, std::function<void()> fn, int rt_priority = 0) {
    if (running_.exchange(true)) return;
    thread_ = std::thread([this, period_us, rt_priority, f = std::move(fn)] {
      realtime_.store(hal::request_realtime_priority(rt_priority));
      auto next = std::chrono::steady_clock::now();
      auto last_start = next;
      bool first = true;
      while (running_.load()) {
        const auto start = std::chrono::steady_clock::now();
        const std::int64_t gap_us =
            std::chrono::duration_cast<std::chrono::microseconds>(start - last_start).count();
        if (!first && gap_us > longest_gap_us_.load()) longest_gap_us_.store(gap_us);
        first = false;
        last_start = start;
        f();
        cycles_.fetch_add(1);
        next += std::chrono::microseconds(period_us);
        const auto now = std::chrono::steady_clock::now();
        const std::int64_t took_us =
            std::chrono::duration_cast<std::chrono::microseconds>(now - start).count();
        if (took_us > longest_cycle_us_.load()) longest_cycle_us_.store(took_us);
        if (next < now) {
          overruns_.fetch_add(1);
          next = now;
        }
        std::this_thread::sleep_until(next);
      }
    });
  }
  void stop() {
    if (!running_.exchange(false)) return;
    if (thread_.joinable()) thread_.join();
  }
  CycleStats stats() const {
    CycleStats s;
    s.cycles = cycles_.load();
    s.overruns = overruns_.load();
    s.longest_gap_us = longest_gap_us_.load();
    s.longest_cycle_us = longest_cycle_us_.load();
    s.realtime = realtime_.load();
    return s;
  }

 private:
  std::atomic<bool> running_{false};
  std::atomic<std::int64_t> cycles_{0}, overruns_{0}, longest_gap_us_{0}, longest_cycle_us_{0};
  std::atomic<hal::RealtimeStatus> realtime_{hal::RealtimeStatus::kNotRequested};
  std::thread thread_;
};

}  // namespace fsw_app
