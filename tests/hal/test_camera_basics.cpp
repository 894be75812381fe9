#include <cmath>

#include "cmocka_cpp.hpp"
#include "hal/camera_status.hpp"
#include "hal/clock.hpp"
#include "hal/depth_frame.hpp"
#include "hal/use_case.hpp"

namespace {

void test_status_strings(void**) {
  assert_string_equal(hal::to_string(hal::CameraStatus::kSuccess), "SUCCESS");
  assert_string_equal(hal::to_string(hal::CameraStatus::kDisconnected), "DISCONNECTED");
  assert_string_equal(hal::to_string(hal::CameraStatus::kInsufficientBandwidth),
                      "INSUFFICIENT_BANDWIDTH");
  assert_int_equal(static_cast<int>(hal::CameraStatus::kUseCaseNotSupported), 5001);
  assert_string_equal(hal::to_string(static_cast<hal::CameraStatus>(1)), "UNKNOWN_STATUS");
}

void test_use_cases(void**) {
  std::size_t n = 0;
  const hal::UseCase* all = hal::use_cases(&n);
  assert_int_equal(n, 6);
  assert_string_equal(all[0].name, "MODE_9_5FPS_2000");
  const hal::UseCase* fast = hal::find_use_case("MODE_5_45FPS_500");
  assert_non_null(fast);
  assert_int_equal(fast->raw_frames, 5);
  assert_int_equal(hal::frame_period_us(*fast), 22222);  // the 22 ms budget at 45 fps
  assert_null(hal::find_use_case("MODE_9_99FPS"));
}

void test_validity(void**) {
  hal::DepthPoint p{0.1f, 0.2f, 0.5f, 0.001f, 10, 255};
  assert_true(hal::is_valid(p));
  p.confidence = 0;
  assert_false(hal::is_valid(p));
  p = {NAN, 0.2f, 0.5f, 0.0f, 0, 255};
  assert_false(hal::is_valid(p));
  p = {0.0f, 0.0f, 0.0f, 0.0f, 0, 255};
  assert_false(hal::is_valid(p));
}

void test_clocks(void**) {
  hal::MonotonicClock mono;
  const std::int64_t a = mono.now_us(), b = mono.now_us();
  assert_true(b >= a);
  hal::ManualClock manual(100);
  manual.advance_us(50);
  assert_int_equal(manual.now_us(), 150);
}

}  // namespace

int main() {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_status_strings),
      cmocka_unit_test(test_use_cases),
      cmocka_unit_test(test_validity),
      cmocka_unit_test(test_clocks),
  };
  return cmocka_run_group_tests(tests, nullptr, nullptr);
}
