// The Pico Flexx USB driver, real libusb code, against the emulated camera
// under umockdev (usb_camera_rig.hpp), when the link fails: stall recovery,
// the recovery ladder up to the USB reset, a silent camera lost and found
// again, unplug and replug, a camera lost when not back in time then found,
// and capture stopped and started after a loss. Commands, streaming and
// spoilt frames are in test_usb_camera_streaming.cpp.
#include <chrono>
#include <cstdio>
#include <string>

#include "sim_hal/umockdev_preload.hpp"
#include "usb_camera_rig.hpp"

namespace {

using pico_flexx::CameraState;
using pico_flexx::LostReason;
using pico_flexx::StreamHealth;
using pico_flexx::UsbStatus;
using usb_camera_rig::CheckingListener;
using usb_camera_rig::default_config;
using usb_camera_rig::frames_arrive;
using usb_camera_rig::g_rig;
using usb_camera_rig::sleep_ms;
using usb_camera_rig::wait_for;

void test_stall_recovery(void**) {
  pico_flexx::UsbCamera cam(default_config(), g_rig->clock);
  assert_int_equal(cam.open(), UsbStatus::kOk);
  CheckingListener listener;
  assert_int_equal(cam.start_streaming(&listener), UsbStatus::kOk);
  assert_true(frames_arrive(listener, 5, 5000));
  const std::uint64_t clears_before = g_rig->camera->counts().clear_halts;
  g_rig->camera->stall_stream();
  // The halt is cleared (the ladder's first rung) and frames flow again.
  assert_true(wait_for([&] { return cam.counters().stalls > 0; }, 2000));
  assert_true(frames_arrive(listener, 10, 2000));
  const pico_flexx::UsbCounters c = cam.counters();
  assert_int_equal(c.clear_halts, 1);
  assert_int_equal(c.usb_resets, 0);
  assert_int_equal(g_rig->camera->counts().clear_halts, clears_before + 1);
  assert_int_equal(cam.state(), CameraState::kStreaming);
  assert_int_equal(cam.stop_streaming(), UsbStatus::kOk);
  assert_int_equal(listener.bad_frames.load(), 0);
}

// A halt that clearing does not lift: the ladder climbs past the
// re-initialisation to the USB reset, which lifts it.
void test_ladder_to_usb_reset(void**) {
  pico_flexx::UsbCamera cam(default_config(), g_rig->clock);
  assert_int_equal(cam.open(), UsbStatus::kOk);
  CheckingListener listener;
  assert_int_equal(cam.start_streaming(&listener), UsbStatus::kOk);
  assert_true(frames_arrive(listener, 5, 5000));
  const std::uint64_t resets_before = g_rig->camera->counts().resets;
  g_rig->camera->stall_stream(true);
  assert_true(wait_for([&] { return cam.counters().usb_resets > 0; }, 5000));
  assert_true(frames_arrive(listener, 10, 3000));
  const pico_flexx::UsbCounters c = cam.counters();
  std::printf(
      "persistent stall: %llu stalls, %llu clear halts, %llu re-initialisations, %llu resets\n",
      static_cast<unsigned long long>(c.stalls), static_cast<unsigned long long>(c.clear_halts),
      static_cast<unsigned long long>(c.reinitialisations),
      static_cast<unsigned long long>(c.usb_resets));
  assert_int_equal(c.clear_halts, 1);
  assert_int_equal(c.reinitialisations, 1);
  assert_int_equal(c.usb_resets, 1);
  assert_int_equal(g_rig->camera->counts().resets, resets_before + 1);
  assert_int_equal(cam.state(), CameraState::kStreaming);
  // The camera came back from its reset in its power-up use case; the
  // driver put its own back.
  assert_int_equal(g_rig->camera->counts().use_case_index, 5);
  assert_int_equal(cam.stop_streaming(), UsbStatus::kOk);
  assert_int_equal(listener.bad_frames.load(), 0);
}

// A camera that streams nothing through every rung: lost, SILENT. The
// driver goes on looking for it, backing off, with no busy loop; when it
// streams again it is found again, without a restart.
void test_silent_camera_lost_and_found_again(void**) {
  pico_flexx::UsbCamera cam(default_config(), g_rig->clock);
  assert_int_equal(cam.open(), UsbStatus::kOk);
  CheckingListener listener;
  assert_int_equal(cam.start_streaming(&listener), UsbStatus::kOk);
  assert_true(frames_arrive(listener, 3, 5000));
  g_rig->camera->set_silent(true);
  assert_true(wait_for([&] { return cam.state() == CameraState::kLost; }, 6000));
  const pico_flexx::UsbCounters c = cam.counters();
  assert_int_equal(cam.lost_reason(), LostReason::kSilent);
  assert_int_equal(cam.health(), StreamHealth::kSilent);
  assert_int_equal(c.silences, 4);  // one per rung, and the last gives up
  assert_int_equal(c.clear_halts, 1);
  assert_int_equal(c.reinitialisations, 1);
  assert_int_equal(c.usb_resets, 1);
  // Still silent: lost it stays, searched at 100, 300, 700, 1500 ms...
  bool left_lost = false;
  for (int i = 0; i < 150; ++i) {
    left_lost = left_lost || cam.state() != CameraState::kLost;
    sleep_ms(10);
  }
  const std::uint64_t attempts = cam.counters().reacquire_attempts;
  std::printf("silent camera lost: %llu searches in 1.5 s\n",
              static_cast<unsigned long long>(attempts));
  assert_false(left_lost);
  assert_true(attempts >= 2);
  assert_true(attempts <= 8);
  g_rig->camera->set_silent(false);
  assert_true(wait_for([&] { return cam.state() == CameraState::kStreaming; }, 10000));
  assert_true(frames_arrive(listener, 10, 5000));
  assert_int_equal(cam.lost_reason(), LostReason::kNone);
  assert_int_equal(cam.counters().reacquisitions, 1);
  assert_true(wait_for([&] { return cam.health() == StreamHealth::kOk; }, 2000));
  assert_int_equal(cam.stop_streaming(), UsbStatus::kOk);
  assert_int_equal(listener.bad_frames.load(), 0);
}

void test_unplug_and_replug(void**) {
  pico_flexx::UsbCamera cam(default_config(), g_rig->clock);
  assert_int_equal(cam.open(), UsbStatus::kOk);
  CheckingListener listener;
  assert_int_equal(cam.start_streaming(&listener), UsbStatus::kOk);
  assert_true(frames_arrive(listener, 5, 5000));
  g_rig->camera->unplug();
  assert_true(wait_for([&] { return cam.state() == CameraState::kWaitingForDevice; }, 2000));
  assert_int_equal(cam.counters().unplugs, 1);
  sleep_ms(300);
  std::string error;
  const auto replugged = std::chrono::steady_clock::now();
  assert_true(g_rig->camera->replug(&error));
  // Streaming again within 2 s of the cable going back in.
  assert_true(frames_arrive(listener, 1, 2000));
  const double back_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - replugged).count();
  std::printf("unplug and replug: streaming again %.3f s after the replug\n", back_s);
  assert_true(frames_arrive(listener, 10, 2000));
  assert_int_equal(cam.state(), CameraState::kStreaming);
  assert_int_equal(cam.counters().replugs, 1);
  assert_int_equal(cam.stop_streaming(), UsbStatus::kOk);
  assert_int_equal(listener.bad_frames.load(), 0);
}

// Unplugged for longer than the reconnect window: lost, with the reason.
// The driver goes on looking, backing off; replugged, the camera streams
// again without a restart of the program.
void test_lost_when_not_back_then_found(void**) {
  pico_flexx::UsbCameraConfig config = default_config();
  config.reconnect_window_ms = 500;
  pico_flexx::UsbCamera cam(config, g_rig->clock);
  assert_int_equal(cam.open(), UsbStatus::kOk);
  CheckingListener listener;
  assert_int_equal(cam.start_streaming(&listener), UsbStatus::kOk);
  assert_true(frames_arrive(listener, 3, 5000));
  g_rig->camera->unplug();
  assert_true(wait_for([&] { return cam.state() == CameraState::kLost; }, 3000));
  assert_int_equal(cam.lost_reason(), LostReason::kUnplugged);
  assert_string_equal(pico_flexx::to_string(cam.lost_reason()), "UNPLUGGED");
  assert_int_equal(cam.health(), StreamHealth::kNoDevice);
  sleep_ms(1000);
  const std::uint64_t attempts = cam.counters().reacquire_attempts;
  assert_true(attempts >= 1);
  assert_true(attempts <= 8);  // backing off, not spinning
  assert_int_equal(cam.state(), CameraState::kLost);
  std::string error;
  assert_true(g_rig->camera->replug(&error));
  assert_true(wait_for([&] { return cam.state() == CameraState::kStreaming; }, 5000));
  assert_true(frames_arrive(listener, 10, 5000));
  assert_int_equal(cam.lost_reason(), LostReason::kNone);
  assert_int_equal(cam.counters().reacquisitions, 1);
  assert_int_equal(cam.stop_streaming(), UsbStatus::kOk);
  assert_int_equal(listener.bad_frames.load(), 0);
}

// Lost, then the capture stopped and started again: refused while the
// camera is away (NO_DEVICE), and streaming once it is back.
void test_stop_and_start_after_lost(void**) {
  pico_flexx::UsbCameraConfig config = default_config();
  config.reconnect_window_ms = 500;
  pico_flexx::UsbCamera cam(config, g_rig->clock);
  assert_int_equal(cam.open(), UsbStatus::kOk);
  CheckingListener listener;
  assert_int_equal(cam.start_streaming(&listener), UsbStatus::kOk);
  assert_true(frames_arrive(listener, 3, 5000));
  g_rig->camera->unplug();
  assert_true(wait_for([&] { return cam.state() == CameraState::kLost; }, 3000));
  assert_int_equal(cam.stop_streaming(), UsbStatus::kOk);
  assert_false(cam.capture_requested());
  assert_int_equal(cam.start_streaming(&listener), UsbStatus::kNoDevice);
  assert_false(cam.capture_requested());
  std::string error;
  assert_true(g_rig->camera->replug(&error));
  // Found by the driver's own search; open, not streaming, as it was left.
  assert_true(wait_for([&] { return cam.state() == CameraState::kOpen; }, 5000));
  assert_int_equal(cam.start_streaming(&listener), UsbStatus::kOk);
  assert_true(frames_arrive(listener, 10, 5000));
  assert_int_equal(cam.state(), CameraState::kStreaming);
  assert_int_equal(cam.stop_streaming(), UsbStatus::kOk);
  assert_int_equal(cam.stop_streaming(), UsbStatus::kNotStreaming);
  assert_int_equal(listener.bad_frames.load(), 0);
}

}  // namespace

int main(int, char** argv) {
  sim_hal::umockdev_preload::ensure(argv);
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_stall_recovery),
      cmocka_unit_test(test_ladder_to_usb_reset),
      cmocka_unit_test(test_silent_camera_lost_and_found_again),
      cmocka_unit_test(test_unplug_and_replug),
      cmocka_unit_test(test_lost_when_not_back_then_found),
      cmocka_unit_test(test_stop_and_start_after_lost),
  };
  return cmocka_run_group_tests(tests, usb_camera_rig::setup_rig, usb_camera_rig::teardown_rig);
}
