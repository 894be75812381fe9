// hal::DepthCamera on the royale API (drivers/pico_flexx/royale_hal), here
// built on the project's royale, against the emulated camera through real
// libusb under umockdev's preload library: a wall 1 m ahead must come out
// 1 m ahead through hal's listener, with the camera's own lens, the use
// case set through royale, capture times on the host's monotonic clock,
// and no allocation per frame. The capture-clock mapping on its own:
// drivers_capture_clock_map.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <mutex>
#include <thread>
#include <vector>

#include "allocation_counter.hpp"
#include "cmocka_cpp.hpp"
#include "emulated_wall_rig.hpp"
#include "pico_flexx/royale_depth_camera.hpp"
#include "sim_hal/umockdev_preload.hpp"

namespace {

// The emulated camera, shared by the tests: a wall 1 m ahead.
using Rig = testing_support::EmulatedWallRig;
Rig* g_rig = nullptr;

int set_up(void**) {
  g_rig = new Rig;
  std::string error;
  if (!g_rig->plug_in(&error)) {
    std::fprintf(stderr, "%s\n", error.c_str());
    return -1;
  }
  return 0;
}

int tear_down(void**) {
  delete g_rig;
  return 0;
}

// Keeps the centre depths, the capture times against arrival, and counts
// the allocations on the camera's thread from the end of frame kArmAt's
// call to the start of frame kDisarmAt's.
struct WallListener final : hal::DepthDataListener {
  static constexpr long kArmAt = 2, kDisarmAt = 7;
  // Room for every frame's depth, so that the listener allocates nothing.
  explicit WallListener(const hal::Clock& c) : clock(c) { centre_z_m.reserve(4096); }
  void on_new_data(const hal::DepthFrame& frame) override {
    const std::int64_t now_us = clock.now_us();
    std::lock_guard<std::mutex> lock(mutex);
    if (frames == kDisarmAt) allocations = alloc_counter::disarm();
    ++frames;
    width = frame.width;
    height = frame.height;
    valid_share = static_cast<double>(hal::count_valid(frame)) / (frame.width * frame.height);
    const hal::DepthPoint& p = frame.at(frame.height / 2, frame.width / 2);
    if (hal::is_valid(p)) centre_z_m.push_back(p.z_m);
    times_ok = times_ok && frame.capture_time_us <= now_us &&
               now_us - frame.capture_time_us < 1'000'000 &&
               frame.capture_time_us > last_capture_us;
    ids_ok = ids_ok && frame.frame_id == static_cast<std::uint64_t>(frames);
    last_capture_us = frame.capture_time_us;
    if (frames == kArmAt) alloc_counter::arm();
  }
  long count() {
    std::lock_guard<std::mutex> lock(mutex);
    return frames;
  }
  const hal::Clock& clock;
  std::mutex mutex;
  long frames = 0, allocations = -1;
  std::uint32_t width = 0, height = 0;
  double valid_share = 0.0;
  std::vector<float> centre_z_m;
  std::int64_t last_capture_us = 0;
  bool times_ok = true, ids_ok = true;
};

void test_wall_through_royale(void**) {
  const Rig& rig = *g_rig;
  pico_flexx::RoyaleDepthCamera camera(pico_flexx::RoyaleCameraConfig{}, rig.clock);
  WallListener listener(rig.clock);
  assert_int_equal(camera.start_capture(), hal::CameraStatus::kDeviceNotInitialized);
  const hal::CameraStatus init = camera.initialize();
  if (init != hal::CameraStatus::kSuccess) fail_msg("initialize: %s", camera.error().c_str());
  assert_int_equal(camera.initialize(), hal::CameraStatus::kDeviceAlreadyInitialized);
  assert_string_equal(camera.id().c_str(), rig.config.serial.c_str());
  std::uint32_t w = 0, h = 0;
  assert_int_equal(camera.max_frame_size(&w, &h), hal::CameraStatus::kSuccess);
  assert_int_equal(w, 224);
  assert_int_equal(h, 171);
  hal::LensParameters lens;
  assert_int_equal(camera.lens_parameters(&lens), hal::CameraStatus::kSuccess);
  assert_near(lens.fx_px, rig.truth.lens.fx_px, 0.01);  // the camera's own, over USB and royale
  assert_near(lens.cy_px, rig.truth.lens.cy_px, 0.01);
  assert_near(lens.k1, rig.truth.lens.k1, 1e-6);
  assert_int_equal(camera.set_use_case("MODE_7_NONE"), hal::CameraStatus::kUseCaseNotSupported);
  assert_int_equal(camera.set_use_case(nullptr), hal::CameraStatus::kInvalidValue);
  assert_int_equal(camera.set_use_case("MODE_9_10FPS_1000"), hal::CameraStatus::kSuccess);
  const hal::UseCase* use_case = nullptr;
  assert_int_equal(camera.current_use_case(&use_case), hal::CameraStatus::kSuccess);
  assert_string_equal(use_case->name, "MODE_9_10FPS_1000");
  assert_int_equal(camera.set_exposure_time(2000), hal::CameraStatus::kExposureTimeNotSupported);
  assert_int_equal(camera.set_exposure_time(800), hal::CameraStatus::kSuccess);
  assert_int_equal(camera.set_exposure_mode(hal::ExposureMode::kAutomatic),
                   hal::CameraStatus::kSuccess);
  assert_int_equal(camera.start_capture(), hal::CameraStatus::kLogicError);  // no listener
  assert_int_equal(camera.register_data_listener(nullptr), hal::CameraStatus::kInvalidValue);
  assert_int_equal(camera.register_data_listener(&listener), hal::CameraStatus::kSuccess);
  assert_true(camera.is_connected());
  assert_int_equal(camera.start_capture(), hal::CameraStatus::kSuccess);
  assert_true(camera.is_capturing());
  for (int waited_ms = 0; waited_ms < 20000 && listener.count() < 10; waited_ms += 50) {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  assert_int_equal(camera.stop_capture(), hal::CameraStatus::kSuccess);
  assert_false(camera.is_capturing());
  std::lock_guard<std::mutex> lock(listener.mutex);
  std::vector<float> z = listener.centre_z_m;
  std::sort(z.begin(), z.end());
  const pico_flexx::RoyaleFrameCounts counts = camera.counts();
  std::printf(
      "wall at 1 m through royale: %ld frames %ux%u, %.1f %% valid, centre median %.4f m over "
      "%zu, capture clock %s, %ld allocations on the camera's thread over %ld frames\n",
      listener.frames, listener.width, listener.height, 100.0 * listener.valid_share,
      z.empty() ? 0.0 : z[z.size() / 2], z.size(), pico_flexx::to_string(camera.capture_clock()),
      listener.allocations, WallListener::kDisarmAt - WallListener::kArmAt);
  assert_true(listener.frames >= 10);
  assert_int_equal(listener.width, 224);
  assert_int_equal(listener.height, 171);
  assert_true(listener.valid_share > 0.95);
  assert_true(z.size() >= 8);
  assert_near(z[z.size() / 2], 1.0, 0.01);
  // The project's royale stamps epoch time, which the camera moves back to
  // the host's monotonic clock exactly: the same clock.
  assert_int_equal(camera.capture_clock(), pico_flexx::CaptureClock::kSame);
  assert_true(listener.times_ok);
  assert_true(listener.ids_ok);
  assert_int_equal(counts.delivered, listener.frames);
  assert_int_equal(counts.malformed, 0);
  assert_true(listener.allocations >= 0);  // the window closed
#if defined(__SANITIZE_ADDRESS__)
  // Only operator new is counted here: none on the camera's thread, the
  // copies (royale's DepthData, then hal's frame) and the processing included.
  // Outside the sanitizer libusb's per-transfer callocs count too
  // (drivers_usb_camera_streaming bounds those).
  assert_int_equal(listener.allocations, 0);
#endif
}

void test_wrong_serial_named(void**) {
  pico_flexx::RoyaleCameraConfig cfg;
  cfg.serial = "0000-0000-0000";
  pico_flexx::RoyaleDepthCamera camera(cfg, g_rig->clock);
  assert_int_equal(camera.initialize(), hal::CameraStatus::kCouldNotOpen);
  std::printf("wrong serial: %s\n", camera.error().c_str());
  assert_non_null(std::strstr(camera.error().c_str(), "no camera with serial 0000-0000-0000"));
  assert_non_null(std::strstr(camera.error().c_str(), g_rig->config.serial.c_str()));
  assert_false(camera.is_connected());
  hal::LensParameters lens;
  assert_int_equal(camera.lens_parameters(&lens), hal::CameraStatus::kDeviceNotInitialized);
}

}  // namespace

int main(int, char** argv) {
  sim_hal::umockdev_preload::ensure(argv);
  const struct CMUnitTest tests[] = {cmocka_unit_test(test_wall_through_royale),
                                     cmocka_unit_test(test_wrong_serial_named)};
  return cmocka_run_group_tests(tests, set_up, tear_down);
}
