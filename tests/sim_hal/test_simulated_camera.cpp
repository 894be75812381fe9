// The simulated camera through the hal interface: status codes, frames
// delivered to the listener in order, stamped by the injected clock.
#include <atomic>
#include <string>
#include <thread>

#include "cmocka_cpp.hpp"
#include "sim_hal/simulated_camera.hpp"

namespace {

const char* kScenario = R"({
  "name": "cam", "seed": 4,
  "scene": {"walls": [{"center": [0, 0, 0], "normal": [1, 0, 0], "size": [3, 3]}]},
  "poses": [{"position": [0.8, 0, 0], "frames": 4}]
})";

// Runs on the camera's thread in free-running capture, so it records what it
// saw and the test thread asserts (a cmocka failure must not longjmp across
// threads).
class Recorder final : public hal::DepthDataListener {
 public:
  void on_new_data(const hal::DepthFrame& frame) override {
    in_order =
        in_order && frame.frame_id == count.load() && frame.width == 224 && frame.height == 171;
    last_time_us = frame.capture_time_us;
    valid = hal::count_valid(frame);
    ++count;
  }
  std::atomic<std::uint64_t> count{0};
  std::atomic<bool> in_order{true};
  std::atomic<std::int64_t> last_time_us{0};
  std::atomic<std::size_t> valid{0};
};

sim_hal::Scenario load() {
  sim_hal::Scenario s;
  std::string error;
  assert_true(sim_hal::parse_scenario(kScenario, "cam.json", &s, &error));
  return s;
}

void test_status_codes(void**) {
  const sim_hal::Scenario s = load();
  hal::ManualClock clock;
  sim_hal::SimulatedCamera cam(s, clock, sim_hal::SimulatedCamera::Pacing::kAsFastAsPossible);
  assert_int_equal(static_cast<int>(cam.set_use_case("MODE_5_45FPS_500")),
                   static_cast<int>(hal::CameraStatus::kDeviceNotInitialized));
  assert_int_equal(static_cast<int>(cam.initialize()),
                   static_cast<int>(hal::CameraStatus::kSuccess));
  assert_int_equal(static_cast<int>(cam.initialize()),
                   static_cast<int>(hal::CameraStatus::kDeviceAlreadyInitialized));
  assert_int_equal(static_cast<int>(cam.set_use_case("MODE_9_1FPS")),
                   static_cast<int>(hal::CameraStatus::kUseCaseNotSupported));
  assert_int_equal(static_cast<int>(cam.set_use_case("MODE_5_45FPS_500")),
                   static_cast<int>(hal::CameraStatus::kSuccess));
  const hal::UseCase* uc = nullptr;
  assert_int_equal(static_cast<int>(cam.current_use_case(&uc)),
                   static_cast<int>(hal::CameraStatus::kSuccess));
  assert_int_equal(uc->frame_rate_hz, 45);
  assert_int_equal(static_cast<int>(cam.set_exposure_time(300)),
                   static_cast<int>(hal::CameraStatus::kExposureModeInvalid));
  assert_int_equal(static_cast<int>(cam.set_exposure_mode(hal::ExposureMode::kManual)),
                   static_cast<int>(hal::CameraStatus::kSuccess));
  assert_int_equal(static_cast<int>(cam.set_exposure_time(800)),
                   static_cast<int>(hal::CameraStatus::kExposureTimeNotSupported));
  assert_int_equal(static_cast<int>(cam.set_exposure_time(300)),
                   static_cast<int>(hal::CameraStatus::kSuccess));
  hal::LensParameters lens;
  assert_int_equal(static_cast<int>(cam.lens_parameters(&lens)),
                   static_cast<int>(hal::CameraStatus::kSuccess));
  assert_true(lens.fx_px > 100.0);
}

void test_lock_step_frames(void**) {
  const sim_hal::Scenario s = load();
  hal::ManualClock clock(1000);
  sim_hal::SimulatedCamera cam(s, clock, sim_hal::SimulatedCamera::Pacing::kAsFastAsPossible);
  Recorder rec;
  assert_int_equal(static_cast<int>(cam.initialize()),
                   static_cast<int>(hal::CameraStatus::kSuccess));
  assert_int_equal(static_cast<int>(cam.register_data_listener(&rec)),
                   static_cast<int>(hal::CameraStatus::kSuccess));
  for (int k = 0; k < 4; ++k) {
    assert_int_equal(static_cast<int>(cam.capture_next()),
                     static_cast<int>(hal::CameraStatus::kSuccess));
    assert_int_equal(rec.last_time_us.load(), 1000 + 500 * k);  // stamped by the injected clock
    clock.advance_us(500);
  }
  assert_int_equal(rec.count.load(), 4);
  assert_true(rec.in_order);
  assert_true(rec.valid > 30000);
  assert_int_equal(static_cast<int>(cam.capture_next()),
                   static_cast<int>(hal::CameraStatus::kDataNotFound));
}

void test_free_running_capture(void**) {
  const sim_hal::Scenario s = load();
  hal::MonotonicClock clock;
  sim_hal::SimulatedCamera cam(s, clock, sim_hal::SimulatedCamera::Pacing::kAsFastAsPossible);
  Recorder rec;
  (void)cam.initialize();
  (void)cam.register_data_listener(&rec);
  assert_int_equal(static_cast<int>(cam.start_capture()),
                   static_cast<int>(hal::CameraStatus::kSuccess));
  assert_int_equal(static_cast<int>(cam.register_data_listener(&rec)),
                   static_cast<int>(hal::CameraStatus::kDeviceIsBusy));
  // It stops by itself after the last pose; wait for that, boundedly.
  for (int k = 0; k < 2000 && cam.is_capturing(); ++k)
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  assert_false(cam.is_capturing());
  assert_int_equal(static_cast<int>(cam.stop_capture()),
                   static_cast<int>(hal::CameraStatus::kSuccess));
  assert_int_equal(rec.count.load(), 4);
  assert_true(rec.in_order);
  assert_int_equal(cam.frames_delivered(), 4);
}

}  // namespace

int main() {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_status_codes),
      cmocka_unit_test(test_lock_step_frames),
      cmocka_unit_test(test_free_running_capture),
  };
  return cmocka_run_group_tests(tests, nullptr, nullptr);
}
