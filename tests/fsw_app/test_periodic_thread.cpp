// The periodic thread's bookkeeping (cycles, overruns, the longest gap)
// and the real-time request's outcomes. The figures asserted are the
// thread's own account of a cycle made deliberately long, not a speed.
#include <pthread.h>
#include <sched.h>

#include <atomic>
#include <chrono>
#include <thread>

#include "cmocka_cpp.hpp"
#include "fsw_app/periodic_thread.hpp"
#include "hal/realtime.hpp"

namespace {

void test_a_long_cycle_is_an_overrun_and_the_longest_gap(void**) {
  fsw_app::PeriodicThread thread;
  std::atomic<int> calls{0};
  thread.start(5000, [&calls] {
    // The third cycle takes 40 ms against a 5 ms period.
    if (calls.fetch_add(1) == 2) std::this_thread::sleep_for(std::chrono::milliseconds(40));
  });
  while (calls.load() < 8) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  thread.stop();
  const fsw_app::CycleStats s = thread.stats();
  assert_true(s.cycles >= 8);
  assert_true(s.overruns >= 1);
  assert_true(s.longest_gap_us >= 40000);
  assert_int_equal(static_cast<int>(s.realtime),
                   static_cast<int>(hal::RealtimeStatus::kNotRequested));
  // Stopped means stopped: no call after stop() returns.
  const int after = calls.load();
  std::this_thread::sleep_for(std::chrono::milliseconds(20));
  assert_int_equal(calls.load(), after);
}

void test_realtime_request_outcomes(void**) {
  assert_int_equal(static_cast<int>(hal::request_realtime_priority(0)),
                   static_cast<int>(hal::RealtimeStatus::kNotRequested));
  assert_int_equal(static_cast<int>(hal::request_realtime_priority(100)),
                   static_cast<int>(hal::RealtimeStatus::kInvalid));
  assert_int_equal(static_cast<int>(hal::request_realtime_priority(-3)),
                   static_cast<int>(hal::RealtimeStatus::kInvalid));
  // In a thread of its own, so this test's thread keeps its scheduler.
  hal::RealtimeStatus got = hal::RealtimeStatus::kFailed;
  int policy = -1;
  std::thread t([&] {
    got = hal::request_realtime_priority(10);
    sched_param p{};
    pthread_getschedparam(pthread_self(), &policy, &p);
  });
  t.join();
  // Either granted (and then really SCHED_FIFO) or refused for want of
  // privilege (and then still the normal scheduler): never a silent miss.
  if (got == hal::RealtimeStatus::kGranted) {
    assert_int_equal(policy, SCHED_FIFO);
  } else {
    assert_int_equal(static_cast<int>(got), static_cast<int>(hal::RealtimeStatus::kNotPermitted));
    assert_int_equal(policy, SCHED_OTHER);
  }
  assert_string_equal(hal::to_string(hal::RealtimeStatus::kNotPermitted), "NOT_PERMITTED");
}

}  // namespace

int main() {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_a_long_cycle_is_an_overrun_and_the_longest_gap),
      cmocka_unit_test(test_realtime_request_outcomes),
  };
  return cmocka_run_group_tests(tests, nullptr, nullptr);
}
