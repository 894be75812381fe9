// The Pico Flexx USB driver, real libusb code, against the emulated camera
// under umockdev (usb_camera_rig.hpp), while the link holds: enumeration,
// commands and their failures, use-case change, streaming without loss and
// with no allocation per frame, capture times from the camera's clock, a
// slow host, corrupt and short frames (each
// counted once), a stream of nothing but corrupt frames, bad headers
// counted once per frame. The link's faults and their recovery are in
// test_usb_camera_recovery.cpp.
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

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

void test_enumeration_and_identity(void**) {
  pico_flexx::UsbCamera cam(default_config(), g_rig->clock);
  assert_int_equal(cam.init_status(), UsbStatus::kOk);
  assert_int_equal(cam.open(), UsbStatus::kOk);
  assert_int_equal(cam.state(), CameraState::kOpen);
  assert_int_equal(cam.identity().vendor_id, pico_flexx::kVendorId);
  assert_int_equal(cam.identity().product_id, pico_flexx::kProductId);
  assert_string_equal(cam.identity().serial, "0005-1234-0042");
  assert_int_equal(cam.identity().firmware_major, 1);
  assert_int_equal(cam.identity().firmware_minor, 4);
  cam.close();

  // By serial: the right one opens, another is not found.
  pico_flexx::UsbCameraConfig by_serial = default_config();
  std::strcpy(by_serial.serial, "0005-1234-0042");
  pico_flexx::UsbCamera right(by_serial, g_rig->clock);
  assert_int_equal(right.open(), UsbStatus::kOk);
  right.close();
  std::strcpy(by_serial.serial, "0005-9999-0001");
  pico_flexx::UsbCamera wrong(by_serial, g_rig->clock);
  assert_int_equal(wrong.open(), UsbStatus::kNotFound);

  // A vendor/product list without the camera finds nothing; one with it
  // second in the list finds it.
  pico_flexx::UsbCameraConfig others = default_config();
  others.ids[0] = {0x1c28, 0xc033};
  pico_flexx::UsbCamera none(others, g_rig->clock);
  assert_int_equal(none.open(), UsbStatus::kNotFound);
  others.ids[1] = {pico_flexx::kVendorId, pico_flexx::kProductId};
  others.id_count = 2;
  pico_flexx::UsbCamera second(others, g_rig->clock);
  assert_int_equal(second.open(), UsbStatus::kOk);
}

void test_calibration_chunked(void**) {
  pico_flexx::UsbCamera cam(default_config(), g_rig->clock);
  assert_int_equal(cam.open(), UsbStatus::kOk);
  std::string buffer(64 * 1024, '\0');
  std::size_t bytes = 0;
  assert_int_equal(
      cam.read_calibration(reinterpret_cast<std::uint8_t*>(&buffer[0]), buffer.size(), &bytes),
      UsbStatus::kOk);
  assert_int_equal(bytes, g_rig->calibration.size());
  assert_true(buffer.compare(0, bytes, g_rig->calibration) == 0);
  // Too small a buffer is refused before anything is read.
  assert_int_equal(cam.read_calibration(reinterpret_cast<std::uint8_t*>(&buffer[0]), 100, &bytes),
                   UsbStatus::kBadArgument);
}

void test_command_timeout(void**) {
  pico_flexx::UsbCamera cam(default_config(), g_rig->clock);
  assert_int_equal(cam.open(), UsbStatus::kOk);
  g_rig->camera->mute_next_commands(1);
  pico_flexx::Identity id;
  assert_int_equal(cam.identify(&id), UsbStatus::kTimeout);
  assert_int_equal(cam.last_failed_command(), pico_flexx::Command::kIdentify);
  assert_int_equal(cam.counters().command_timeouts, 1);
  // The camera answers again, and the next command is not confused.
  assert_int_equal(cam.identify(&id), UsbStatus::kOk);
  // Refusals carry the camera's reason: an exposure past the use case's
  // longest, a use case that does not exist.
  assert_int_equal(cam.set_exposure_time(5000), UsbStatus::kRefused);
  assert_int_equal(cam.last_refusal(), pico_flexx::ReplyStatus::kOutOfRange);
  assert_int_equal(cam.set_use_case(17), UsbStatus::kRefused);
  assert_int_equal(cam.last_refusal(), pico_flexx::ReplyStatus::kOutOfRange);
  assert_int_equal(cam.counters().command_refusals, 2);
}

void test_use_case_change(void**) {
  pico_flexx::UsbCamera cam(default_config(), g_rig->clock);
  assert_int_equal(cam.open(), UsbStatus::kOk);
  assert_int_equal(g_rig->camera->counts().use_case_index, 5);
  assert_int_equal(cam.set_use_case(3), UsbStatus::kOk);  // MODE_9_25FPS_450
  assert_int_equal(g_rig->camera->counts().use_case_index, 3);
  CheckingListener listener;
  assert_int_equal(cam.start_streaming(&listener), UsbStatus::kOk);
  assert_true(wait_for([&] { return listener.frames.load() >= 5; }, 5000));
  assert_int_equal(listener.last_mode.load(), tof::Mode::kMode9);
  assert_int_equal(cam.set_use_case(5), UsbStatus::kStreaming);  // not while streaming
  assert_int_equal(cam.stop_streaming(), UsbStatus::kOk);
  assert_int_equal(cam.set_use_case(5), UsbStatus::kOk);
  const long before = listener.frames.load();
  assert_int_equal(cam.start_streaming(&listener), UsbStatus::kOk);
  assert_true(wait_for([&] { return listener.frames.load() >= before + 5; }, 5000));
  assert_int_equal(listener.last_mode.load(), tof::Mode::kMode5);
  assert_int_equal(cam.stop_streaming(), UsbStatus::kOk);
  assert_int_equal(listener.bad_frames.load(), 0);
  assert_int_equal(cam.counters().assembly.dropped(), 0);
}

// 10 s at 45 fps: every frame the camera sends arrives whole and checked,
// none is missed, and the event thread allocates nothing of its own.
void test_streaming_without_loss(void**) {
  pico_flexx::UsbCamera cam(default_config(), g_rig->clock);
  assert_int_equal(cam.open(), UsbStatus::kOk);
  const sim_hal::EmulatorCounts before = g_rig->camera->counts();
  CheckingListener listener;
  listener.arm_at = 20;
  listener.disarm_at = 420;
  listener.camera = &cam;
  const pico_flexx::UsbCounters c0 = cam.counters();
  assert_int_equal(cam.start_streaming(&listener), UsbStatus::kOk);
  sleep_ms(10000);
  assert_int_equal(cam.stop_streaming(), UsbStatus::kOk);
  const sim_hal::EmulatorCounts after = g_rig->camera->counts();
  const pico_flexx::UsbCounters c = cam.counters();
  const long sent = static_cast<long>(after.frames_sent - before.frames_sent);
  std::printf(
      "10 s at 45 fps: %ld frames sent, %ld delivered, %llu missed, %llu dropped, "
      "%llu dropped at the camera; %ld allocations on the event thread over %ld frames "
      "(%ld transfers submitted meanwhile)\n",
      sent, listener.frames.load(), static_cast<unsigned long long>(c.assembly.frames_missed),
      static_cast<unsigned long long>(c.assembly.dropped()),
      static_cast<unsigned long long>(after.frames_dropped_no_transfer -
                                      before.frames_dropped_no_transfer),
      listener.allocations.load(), listener.disarm_at - listener.arm_at,
      listener.submitted_in_window.load());
  assert_true(sent >= 430);  // 450 due; a little slack for start-up on a loaded machine
  // The last frame may have been cut off by the stop.
  assert_true(listener.frames.load() >= sent - 1);
  assert_int_equal(listener.bad_frames.load(), 0);
  assert_int_equal(c.assembly.frames_missed, 0);
  assert_int_equal(after.frames_dropped_no_transfer, before.frames_dropped_no_transfer);
  assert_true(listener.window_done.load());
  // The driver's own code allocates nothing per frame. libusb's Linux
  // backend callocs each submitted transfer's URB array, which the
  // counter sees outside AddressSanitizer (where malloc is counted): at
  // most one per submitted transfer.
  assert_true(listener.submitted_in_window.load() > 0);
  assert_true(listener.allocations.load() <= listener.submitted_in_window.load());
  assert_true(c.transfers_submitted > c0.transfers_submitted);
}

// Capture times from the camera's own clock (its header's stamp, 30 ppm
// off the host's, counting from its power-up), moved to the host's clock
// by the least delay to each frame's first transfer. The driver cannot see
// the fixed part of that delay (readout and the first transfer's trip), so
// against the emulator's capture times (when each frame fell due at the
// imager) the error's floor is the least delay seen, which is longer on a
// loaded or sanitized build: the median error must stay within a
// millisecond of that floor. Midway the listener holds the event thread for
// 300 ms once: the frames that waited in the camera's FIFO arrive up to
// 300 ms late and must still carry their capture times to within 2 ms of
// the floor.
class TimingListener final : public pico_flexx::RawFrameListener {
 public:
  static constexpr int kKept = 200;  // the emulator keeps its newest 256
  void on_raw_frame(const pico_flexx::RawFrameInfo& info, const tof::RawFrame& frame) override {
    const int n = frames++;
    Frame& f = kept[static_cast<std::size_t>(n % kKept)];
    f.sequence = info.sequence;
    f.capture_us = frame.capture_time_us;
    f.first_transfer_us = info.first_transfer_us;
    f.info_agrees = info.capture_time_us == frame.capture_time_us &&
                    info.capture_time_us <= info.first_transfer_us;
    if (n == hold_at) sleep_ms(300);
  }
  struct Frame {
    std::uint32_t sequence = 0;
    std::int64_t capture_us = 0, first_transfer_us = 0;
    bool info_agrees = false;
  };
  std::array<Frame, kKept> kept{};
  std::atomic<int> frames{0};
  int hold_at = -1;
};

void test_capture_times_from_the_camera_clock(void**) {
  pico_flexx::UsbCamera cam(default_config(), g_rig->clock);
  assert_int_equal(cam.open(), UsbStatus::kOk);
  TimingListener listener;
  listener.hold_at = 90;
  assert_int_equal(cam.start_streaming(&listener), UsbStatus::kOk);
  assert_true(wait_for([&] { return listener.frames.load() >= 180; }, 15000));
  assert_int_equal(cam.stop_streaming(), UsbStatus::kOk);
  const int n = std::min(listener.frames.load(), TimingListener::kKept);
  std::vector<double> error_us, arrival_late_us;
  int disagree = 0;
  std::vector<double> held_error_us;  // the frames that waited in the FIFO through the hold
  for (int k = 0; k < n; ++k) {
    const TimingListener::Frame& f = listener.kept[static_cast<std::size_t>(k)];
    std::int64_t truth_us = 0;
    if (!g_rig->camera->capture_time_of(f.sequence, &truth_us)) continue;
    disagree += f.info_agrees ? 0 : 1;
    const double error = std::fabs(static_cast<double>(f.capture_us - truth_us));
    const double late = static_cast<double>(f.first_transfer_us - truth_us);
    error_us.push_back(error);
    arrival_late_us.push_back(late);
    if (late > 100'000) held_error_us.push_back(error);
  }
  assert_true(error_us.size() >= 150);
  std::sort(error_us.begin(), error_us.end());
  std::sort(arrival_late_us.begin(), arrival_late_us.end());
  const double median_us = error_us[error_us.size() / 2];
  const double floor_us = std::max(0.0, arrival_late_us.front());
  int held_ok = 0;
  for (double e : held_error_us) held_ok += e <= floor_us + 2'000.0 ? 1 : 0;
  const int held_frames = static_cast<int>(held_error_us.size());
  std::printf(
      "capture times over %zu frames: |error| median %.0f us, 90th percentile %.0f us, "
      "max %.0f us (first transfer after capture: least %.0f us, median %.0f us, max %.0f us); "
      "%d frames arrived over 100 ms late, %d of them within 2 ms of the least delay\n",
      error_us.size(), median_us, error_us[error_us.size() * 9 / 10], error_us.back(), floor_us,
      arrival_late_us[arrival_late_us.size() / 2], arrival_late_us.back(), held_frames, held_ok);
  assert_int_equal(disagree, 0);
  assert_true(median_us <= floor_us + 1'000.0);
  assert_true(held_frames >= 5);
  assert_true(held_ok >= held_frames - 1);
}

// A host too slow to take its frames: the listener holds the event thread
// for 2 s once, so no transfer is reaped or resubmitted meanwhile. The
// camera's FIFO (45 frames, 1 s at 45 fps) fills and overflows: the frames
// it could not keep are dropped at the camera, and the driver must count
// exactly those as missed (the gap in the sequence numbers), refuse
// nothing, hand on no bad frame, and stream on afterwards.
class StallingListener final : public pico_flexx::RawFrameListener {
 public:
  void on_raw_frame(const pico_flexx::RawFrameInfo& info, const tof::RawFrame& frame) override {
    inner.on_raw_frame(info, frame);
    if (inner.frames.load() == stall_at) sleep_ms(2000);
  }
  CheckingListener inner;
  long stall_at = 20;
};

void test_slow_host_loses_frames_at_the_camera(void**) {
  pico_flexx::UsbCamera cam(default_config(), g_rig->clock);
  assert_int_equal(cam.open(), UsbStatus::kOk);
  const sim_hal::EmulatorCounts before = g_rig->camera->counts();
  StallingListener listener;
  assert_int_equal(cam.start_streaming(&listener), UsbStatus::kOk);
  // The stall, then 45 more frames once the host is back.
  assert_true(
      wait_for([&] { return listener.inner.frames.load() >= listener.stall_at + 45; }, 15000));
  assert_int_equal(cam.stop_streaming(), UsbStatus::kOk);
  const sim_hal::EmulatorCounts after = g_rig->camera->counts();
  const pico_flexx::UsbCounters c = cam.counters();
  const auto dropped_at_camera =
      static_cast<long>(after.frames_dropped_no_transfer - before.frames_dropped_no_transfer);
  std::printf(
      "slow host (event thread held 2 s): %ld frames delivered, %ld dropped at the camera, "
      "%llu missed by the driver, %llu refused, %llu silences, state %s\n",
      listener.inner.frames.load(), dropped_at_camera,
      static_cast<unsigned long long>(c.assembly.frames_missed),
      static_cast<unsigned long long>(c.assembly.dropped()),
      static_cast<unsigned long long>(c.silences), pico_flexx::to_string(cam.state()));
  assert_true(dropped_at_camera >= 20);  // 90 due in 2 s, at most 45 + 4 kept
  assert_int_equal(static_cast<long>(c.assembly.frames_missed), dropped_at_camera);
  assert_int_equal(c.assembly.dropped(), 0);
  assert_int_equal(listener.inner.bad_frames.load(), 0);
  assert_true(cam.state() != CameraState::kLost);
}

void test_corrupt_and_short_frames_dropped(void**) {
  pico_flexx::UsbCamera cam(default_config(), g_rig->clock);
  assert_int_equal(cam.open(), UsbStatus::kOk);
  CheckingListener listener;
  assert_int_equal(cam.start_streaming(&listener), UsbStatus::kOk);
  assert_true(frames_arrive(listener, 5, 5000));
  g_rig->camera->corrupt_next_frames(3);
  assert_true(frames_arrive(listener, 10, 5000));
  g_rig->camera->shorten_next_frames(2);
  assert_true(frames_arrive(listener, 10, 5000));
  assert_int_equal(cam.stop_streaming(), UsbStatus::kOk);
  const pico_flexx::UsbCounters c = cam.counters();
  assert_int_equal(c.assembly.frames_corrupt, 3);
  assert_int_equal(c.assembly.frames_short, 2);
  assert_int_equal(c.assembly.frames_bad_header, 0);
  assert_int_equal(listener.bad_frames.load(), 0);  // none of them handed on
  assert_int_equal(c.frames_delivered, static_cast<std::uint64_t>(listener.frames.load()));
}

// A camera that sends nothing but corrupt frames is there and streaming:
// for longer than the ladder used to take to give it up (2 s), it is
// never silent, never recovering, never lost; each frame is refused once
// and the stream reported CORRUPT_STREAM. Once the corruption stops, good
// frames come at once: nothing was torn down.
void test_corrupt_stream_never_lost(void**) {
  assert_string_equal(pico_flexx::to_string(StreamHealth::kCorruptStream), "CORRUPT_STREAM");
  assert_string_equal(pico_flexx::to_string(LostReason::kTransferErrors), "TRANSFER_ERRORS");
  pico_flexx::UsbCamera cam(default_config(), g_rig->clock);
  assert_int_equal(cam.open(), UsbStatus::kOk);
  assert_int_equal(cam.health(), StreamHealth::kNotStreaming);
  CheckingListener listener;
  assert_int_equal(cam.start_streaming(&listener), UsbStatus::kOk);
  assert_true(frames_arrive(listener, 5, 5000));
  assert_int_equal(cam.health(), StreamHealth::kOk);
  const pico_flexx::UsbCounters c0 = cam.counters();
  const sim_hal::EmulatorCounts e0 = g_rig->camera->counts();
  g_rig->camera->corrupt_next_frames(100000);
  bool left_streaming = false, reported_silent = false, reported_corrupt = false;
  const auto began = std::chrono::steady_clock::now();
  while (std::chrono::steady_clock::now() - began < std::chrono::milliseconds(3500)) {
    left_streaming = left_streaming || cam.state() != CameraState::kStreaming;
    reported_silent = reported_silent || cam.health() == StreamHealth::kSilent;
    reported_corrupt = reported_corrupt || cam.health() == StreamHealth::kCorruptStream;
    sleep_ms(10);
  }
  const pico_flexx::UsbCounters c1 = cam.counters();
  const std::uint64_t refused = c1.assembly.frames_corrupt - c0.assembly.frames_corrupt;
  std::printf("3.5 s of corrupt frames: %llu refused, %llu in a row, state %s, health %s\n",
              static_cast<unsigned long long>(refused),
              static_cast<unsigned long long>(c1.consecutive_bad_frames),
              pico_flexx::to_string(cam.state()), pico_flexx::to_string(cam.health()));
  assert_false(left_streaming);
  assert_false(reported_silent);
  assert_true(reported_corrupt);
  assert_int_equal(cam.health(), StreamHealth::kCorruptStream);
  assert_int_equal(c1.corrupt_streams, c0.corrupt_streams + 1);
  assert_true(refused > 0);
  assert_int_equal(c1.consecutive_bad_frames, refused);
  // The ladder was left alone.
  assert_int_equal(c1.silences, c0.silences);
  assert_int_equal(c1.clear_halts, c0.clear_halts);
  assert_int_equal(c1.reinitialisations, c0.reinitialisations);
  assert_int_equal(c1.usb_resets, c0.usb_resets);

  g_rig->camera->clear_frame_faults();
  const auto cleared = std::chrono::steady_clock::now();
  assert_true(frames_arrive(listener, 1, 1000));
  std::printf("corruption stopped: a good frame %.3f s later\n",
              std::chrono::duration<double>(std::chrono::steady_clock::now() - cleared).count());
  assert_true(frames_arrive(listener, 10, 5000));
  assert_true(wait_for([&] { return cam.health() == StreamHealth::kOk; }, 2000));
  assert_int_equal(cam.counters().consecutive_bad_frames, 0);
  assert_int_equal(cam.stop_streaming(), UsbStatus::kOk);
  assert_int_equal(cam.health(), StreamHealth::kNotStreaming);
  const pico_flexx::UsbCounters c2 = cam.counters();
  const sim_hal::EmulatorCounts e2 = g_rig->camera->counts();
  // Every frame the camera corrupted was refused, once, and nothing else.
  assert_int_equal(c2.assembly.frames_corrupt - c0.assembly.frames_corrupt,
                   e2.frames_corrupted - e0.frames_corrupted);
  assert_int_equal(c2.assembly.dropped() - c0.assembly.dropped(),
                   e2.frames_corrupted - e0.frames_corrupted);
  assert_int_equal(c2.assembly.transfers_discarded, c0.assembly.transfers_discarded);
  assert_int_equal(listener.bad_frames.load(), 0);
}

// MODE_9 frames in 64 KB transfers (11 per frame) with a bad header CRC:
// each frame refused once, not once per transfer, and within the frames
// the driver counts as missed.
void test_bad_headers_counted_once_per_frame(void**) {
  pico_flexx::UsbCameraConfig config = default_config();
  config.use_case_index = 3;  // MODE_9_25FPS_450
  config.transfer_bytes = 64 * 1024;
  config.transfer_count = 8;
  pico_flexx::UsbCamera cam(config, g_rig->clock);
  assert_int_equal(cam.open(), UsbStatus::kOk);
  CheckingListener listener;
  assert_int_equal(cam.start_streaming(&listener), UsbStatus::kOk);
  assert_true(frames_arrive(listener, 3, 10000));
  const pico_flexx::UsbCounters c0 = cam.counters();
  const sim_hal::EmulatorCounts e0 = g_rig->camera->counts();
  g_rig->camera->corrupt_next_headers(3);
  assert_true(frames_arrive(listener, 10, 10000));
  assert_int_equal(cam.stop_streaming(), UsbStatus::kOk);
  const pico_flexx::UsbCounters c = cam.counters();
  const sim_hal::EmulatorCounts e = g_rig->camera->counts();
  const std::uint64_t refused = c.assembly.dropped() - c0.assembly.dropped();
  const std::uint64_t missed = c.assembly.frames_missed - c0.assembly.frames_missed;
  std::printf("3 MODE_9 frames with a bad header: %llu refused, %llu missed, %llu transfers\n",
              static_cast<unsigned long long>(refused), static_cast<unsigned long long>(missed),
              static_cast<unsigned long long>(c.assembly.transfers - c0.assembly.transfers));
  assert_int_equal(e.headers_corrupted - e0.headers_corrupted, 3);
  assert_int_equal(c.assembly.frames_bad_header - c0.assembly.frames_bad_header, 3);
  assert_int_equal(refused, 3);
  assert_int_equal(c.assembly.last_header_error, pico_flexx::ParseStatus::kBadCrc);
  assert_int_equal(c.assembly.transfers_discarded, c0.assembly.transfers_discarded);
  assert_true(missed >= refused);
  assert_int_equal(listener.bad_frames.load(), 0);
}

}  // namespace

int main(int, char** argv) {
  sim_hal::umockdev_preload::ensure(argv);
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_enumeration_and_identity),
      cmocka_unit_test(test_calibration_chunked),
      cmocka_unit_test(test_command_timeout),
      cmocka_unit_test(test_use_case_change),
      cmocka_unit_test(test_streaming_without_loss),
      cmocka_unit_test(test_capture_times_from_the_camera_clock),
      cmocka_unit_test(test_slow_host_loses_frames_at_the_camera),
      cmocka_unit_test(test_corrupt_and_short_frames_dropped),
      cmocka_unit_test(test_corrupt_stream_never_lost),
      cmocka_unit_test(test_bad_headers_counted_once_per_frame),
  };
  return cmocka_run_group_tests(tests, usb_camera_rig::setup_rig, usb_camera_rig::teardown_rig);
}
