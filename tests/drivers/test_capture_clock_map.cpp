// The capture clock map: stamps on the host's clock kept, stamps on
// another clock moved by the least delay over the last one to two windows
// (tighter on a quicker frame, following a drift of the other clock,
// afresh on a step), never after arrival.
#include <algorithm>
#include <cstdint>

#include "cmocka_cpp.hpp"
#include "pico_flexx/capture_clock_map.hpp"

namespace {

using pico_flexx::CaptureClock;
using pico_flexx::CaptureClockMap;
using pico_flexx::CaptureClockMapConfig;

void test_clock_map_same_clock(void**) {
  CaptureClockMap map;
  assert_int_equal(map.clock(), CaptureClock::kUnknown);
  // Stamped 30 ms before arrival on our clock: kept as it is.
  assert_int_equal(map.to_host_us(5'000'000, 5'030'000), 5'000'000);
  assert_int_equal(map.clock(), CaptureClock::kSame);
  assert_int_equal(map.to_host_us(5'200'000, 5'260'000), 5'200'000);
  assert_int_equal(map.reanchors(), 0);
  assert_string_equal(pico_flexx::to_string(map.clock()), "SAME");
}

void test_clock_map_other_clock(void**) {
  CaptureClockMap map;
  // The camera's clock is 1000 s ahead of ours; delays 40, 25, 60 ms.
  const std::int64_t ahead = 1'000'000'000;
  const std::int64_t first = map.to_host_us(ahead + 1'000'000, 1'040'000);
  assert_int_equal(map.clock(), CaptureClock::kMapped);
  assert_int_equal(first, 1'040'000);  // the first delay is the bound: arrival
  const std::int64_t second = map.to_host_us(ahead + 1'200'000, 1'225'000);
  assert_int_equal(second, 1'225'000);  // a quicker frame tightens the bound
  const std::int64_t third = map.to_host_us(ahead + 1'400'000, 1'460'000);
  // 25 ms is the least delay seen: the frame was captured 1.425 s ours.
  assert_int_equal(third, 1'425'000);
  assert_true(third <= 1'460'000);
  assert_int_equal(map.reanchors(), 0);
  // The camera's clock steps back 100 s: the offset starts afresh, counted.
  const std::int64_t stepped = map.to_host_us(ahead - 100'000'000 + 1'600'000, 1'640'000);
  assert_int_equal(map.reanchors(), 1);
  assert_int_equal(stepped, 1'640'000);
  // ... and forward 100 s: counted too.
  (void)map.to_host_us(ahead + 200'000'000, 1'900'000);
  assert_int_equal(map.reanchors(), 2);
  // Never after arrival, whatever the stamp.
  assert_true(map.to_host_us(ahead + 400'000'000, 2'000'000) <= 2'000'000);
}

void test_clock_map_leaves_our_clock(void**) {
  CaptureClockMap map;
  (void)map.to_host_us(3'000'000, 3'010'000);
  assert_int_equal(map.clock(), CaptureClock::kSame);
  // A stamp from the future (another clock after all): mapped, counted.
  assert_int_equal(map.to_host_us(9'000'000, 3'210'000), 3'210'000);
  assert_int_equal(map.clock(), CaptureClock::kMapped);
  assert_int_equal(map.reanchors(), 1);
}

// The camera's clock runs 100 ppm slow against ours (10 times a crystal's
// usual error): a bound learned once would drift 1 ms in 10 s; the
// windowed bound stays within the window's drift (100 us per second) plus
// the least latency, and the window's change reports the drift.
void test_clock_map_follows_a_drifting_clock(void**) {
  CaptureClockMapConfig cfg;
  cfg.same_clock_window_us = -1;  // the stamps are known to be the camera's
  CaptureClockMap map(cfg);
  const std::int64_t period_us = 22'222, camera_origin_us = -7'000'000'000;
  std::int64_t worst_late_us = 0, worst_early_us = 0;
  for (int k = 0; k < 45 * 20; ++k) {
    const std::int64_t capture_us = 1'000'000 + k * period_us;  // ours
    // The camera's counter: 100 ppm slow.
    const std::int64_t stamp_us =
        (capture_us - camera_origin_us) - (capture_us - camera_origin_us) / 10'000;
    // 2 to 9 ms from capture to arrival, the least every tenth frame.
    const std::int64_t arrival_us = capture_us + (k % 10 == 0 ? 2'000 : 2'000 + 700 * (k % 10));
    const std::int64_t mapped_us = map.to_host_us(stamp_us, arrival_us);
    assert_true(mapped_us <= arrival_us);
    if (k < 45 * 3) continue;  // the first windows
    worst_late_us = std::max(worst_late_us, mapped_us - capture_us);
    worst_early_us = std::max(worst_early_us, capture_us - mapped_us);
  }
  assert_int_equal(map.clock(), CaptureClock::kMapped);
  assert_int_equal(map.reanchors(), 0);
  // The least latency (2 ms) late, give or take two windows' drift.
  assert_true(worst_late_us <= 2'000 + 250);
  assert_true(worst_early_us <= 0);
  // 100 ppm: the least delay grows 100 us a second.
  assert_true(map.window_change_us() >= 80 && map.window_change_us() <= 120);
  // A negative same-clock window: even a stamp just before arrival is
  // another clock's.
  CaptureClockMap strict(cfg);
  (void)strict.to_host_us(5'000'000, 5'001'000);
  assert_int_equal(strict.clock(), CaptureClock::kMapped);
}

// A frame that waited 3 s in the camera's FIFO (a host that stalled) is
// neither another clock nor a step: it keeps its capture time.
void test_clock_map_keeps_a_held_frame_s_time(void**) {
  CaptureClockMapConfig cfg;
  cfg.same_clock_window_us = -1;
  CaptureClockMap map(cfg);
  const std::int64_t camera_ahead_us = 5'000'000'000;
  for (int k = 0; k < 20; ++k) {
    const std::int64_t capture_us = 1'000'000 + k * 200'000;
    (void)map.to_host_us(capture_us + camera_ahead_us, capture_us + 2'000);
  }
  const std::int64_t held_capture_us = 5'000'000;
  assert_int_equal(map.to_host_us(held_capture_us + camera_ahead_us, held_capture_us + 3'000'000),
                   held_capture_us + 2'000);
  assert_int_equal(map.reanchors(), 0);
}

}  // namespace

int main() {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_clock_map_same_clock),
      cmocka_unit_test(test_clock_map_other_clock),
      cmocka_unit_test(test_clock_map_leaves_our_clock),
      cmocka_unit_test(test_clock_map_follows_a_drifting_clock),
      cmocka_unit_test(test_clock_map_keeps_a_held_frame_s_time),
  };
  return cmocka_run_group_tests(tests, nullptr, nullptr);
}
