#pragma once
// A thread that calls a function at a fixed period until stopped. An
// overrun does not queue a burst of catch-up calls: the schedule restarts
// from now. The function is stored once, at start.
#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <thread>
#include <utility>

namespace fsw_app {

class PeriodicThread {
 public:
  PeriodicThread() = default;
  PeriodicThread(const PeriodicThread&) = delete;
  PeriodicThread& operator=(const PeriodicThread&) = delete;
  ~PeriodicThread() { stop(); }

  void start(std::int64_t period_us, std::function<void()> fn) {
    if (running_.exchange(true)) return;
    thread_ = std::thread([this, period_us, f = std::move(fn)] {
      auto next = std::chrono::steady_clock::now();
      while (running_.load()) {
        f();
        next += std::chrono::microseconds(period_us);
        const auto now = std::chrono::steady_clock::now();
        if (next < now) next = now;
        std::this_thread::sleep_until(next);
      }
    });
  }
  void stop() {
    if (!running_.exchange(false)) return;
    if (thread_.joinable()) thread_.join();
  }

 private:
  std::atomic<bool> running_{false};
  std::thread thread_;
};

}  // namespace fsw_app
