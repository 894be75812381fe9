// The Pico Flexx USB driver, real libusb code, against the emulated camera
// (sim_hal/emulated_pico_flexx.hpp) under umockdev: enumeration, commands
// and their failures, use-case change, streaming without loss, corrupt
// and short frames (each counted once), a stream of nothing but corrupt
// frames, stall recovery, unplug and replug, a lost camera found again,
// and no allocation per frame. One emulated device serves every test (umockdev allows only
// a few dozen descriptors per process), so the tests run in this order.
#include <atomic>
#include <chrono>
#include <cstring>
#include <memory>
#include <string>
#include <thread>

#include "allocation_counter.hpp"
#include "cmocka_cpp.hpp"
#include "pico_flexx/usb_camera.hpp"
#include "sim_hal/emulated_pico_flexx.hpp"
#include "sim_hal/umockdev_preload.hpp"

namespace {

using pico_flexx::CameraState;
using pico_flexx::LostReason;
using pico_flexx::StreamHealth;
using pico_flexx::UsbStatus;

// Every sample of a frame's images is a function of its sequence number
// and position, so a delivered frame can be checked sample by sample.
std::uint16_t expected_sample(std::uint64_t sequence, std::size_t index) {
  return static_cast<std::uint16_t>((sequence * 131u + index * 7u) & 0xFFFu);
}

class PatternSource final : public sim_hal::RawFrameSource {
 public:
  void fill(std::uint64_t frame_index, const hal::UseCase& use_case, std::uint32_t exposure_us,
            tof::RawFrame* out) override {
    const std::size_t samples = static_cast<std::size_t>(use_case.raw_frames) * tof::kPixels;
    std::uint16_t* p = out->image(0);
    for (std::size_t i = 0; i < samples; ++i) p[i] = expected_sample(frame_index, i);
    out->exposure_us = exposure_us != 0 ? exposure_us : use_case.max_exposure_us;
    out->sensor_temperature_c = 36.5f;
  }
};

// Checks every frame it is given; arms the allocation counter on the
// event thread over a window of frames.
class CheckingListener final : public pico_flexx::RawFrameListener {
 public:
  void on_raw_frame(const pico_flexx::RawFrameInfo& info, const tof::RawFrame& frame) override {
    const std::size_t samples =
        static_cast<std::size_t>(tof::raw_image_count(frame.mode)) * tof::kPixels;
    const std::uint16_t* p = frame.image(0);
    bool ok = frame.frame_id == info.sequence;
    // A sample in every 97 (the whole frame in the streaming test is too
    // slow under the sanitizers to check at 45 fps).
    for (std::size_t i = 0; i < samples && ok; i += 97)
      ok = p[i] == expected_sample(info.sequence, i);
    if (!ok) bad_frames.fetch_add(1);
    last_mode = frame.mode;
    const long n = frames.fetch_add(1) + 1;
    if (n == arm_at) {
      submitted_at_arm = camera->counters().transfers_submitted;
      alloc_counter::arm();
    }
    if (n == disarm_at) {
      allocations = alloc_counter::disarm();
      submitted_in_window =
          static_cast<long>(camera->counters().transfers_submitted - submitted_at_arm);
      window_done = true;
    }
  }
  std::atomic<long> frames{0}, bad_frames{0};
  std::atomic<tof::Mode> last_mode{tof::Mode::kMode9};
  long arm_at = -1, disarm_at = -1;
  pico_flexx::UsbCamera* camera = nullptr;  // for the transfers submitted in the window
  std::uint64_t submitted_at_arm = 0;
  std::atomic<long> allocations{-1}, submitted_in_window{-1};
  std::atomic<bool> window_done{false};
};

struct Rig {
  hal::MonotonicClock clock;
  PatternSource source;
  std::unique_ptr<sim_hal::EmulatedPicoFlexx> camera;
  std::string calibration;
};
Rig* g_rig = nullptr;

pico_flexx::UsbCameraConfig default_config() {
  pico_flexx::UsbCameraConfig c;
  c.use_case_index = 5;  // MODE_5_45FPS_500
  // Every emulated URB is a round trip between this thread and umockdev's,
  // which on a loaded two-core machine can take milliseconds: fewer,
  // larger transfers (a MODE_5 frame in one) keep the stream ahead.
  c.transfer_bytes = 512 * 1024;
  c.transfer_count = 4;
  return c;
}

void sleep_ms(int ms) {
  std::this_thread::sleep_for(std::chrono::milliseconds(ms));
}

// Waits (bounded) for `done`; true when it happened.
template <typename F>
bool wait_for(F done, int timeout_ms) {
  for (int waited = 0; waited < timeout_ms; waited += 10) {
    if (done()) return true;
    sleep_ms(10);
  }
  return done();
}

int setup_rig(void**) {
  g_rig = new Rig;
  // A calibration "file" of 10 kB: three chunks, the last a partial one.
  for (int i = 0; g_rig->calibration.size() < 10000; ++i) {
    g_rig->calibration += "{\"line\": " + std::to_string(i) + "}\n";
  }
  sim_hal::EmulatedCameraConfig config;
  config.calibration = g_rig->calibration;
  std::string error;
  g_rig->camera = sim_hal::EmulatedPicoFlexx::create(config, &g_rig->source, g_rig->clock, &error);
  if (!g_rig->camera) {
    std::fprintf(stderr, "%s\n", error.c_str());
    return -1;
  }
  return 0;
}

int teardown_rig(void**) {
  delete g_rig;
  return 0;
}

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

// Streams until `frames` more frames have arrived (bounded); true if they did.
bool frames_arrive(const CheckingListener& listener, long frames, int timeout_ms) {
  const long target = listener.frames.load() + frames;
  return wait_for([&] { return listener.frames.load() >= target; }, timeout_ms);
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
      cmocka_unit_test(test_enumeration_and_identity),
      cmocka_unit_test(test_calibration_chunked),
      cmocka_unit_test(test_command_timeout),
      cmocka_unit_test(test_use_case_change),
      cmocka_unit_test(test_streaming_without_loss),
      cmocka_unit_test(test_slow_host_loses_frames_at_the_camera),
      cmocka_unit_test(test_corrupt_and_short_frames_dropped),
      cmocka_unit_test(test_corrupt_stream_never_lost),
      cmocka_unit_test(test_bad_headers_counted_once_per_frame),
      cmocka_unit_test(test_stall_recovery),
      cmocka_unit_test(test_ladder_to_usb_reset),
      cmocka_unit_test(test_silent_camera_lost_and_found_again),
      cmocka_unit_test(test_unplug_and_replug),
      cmocka_unit_test(test_lost_when_not_back_then_found),
      cmocka_unit_test(test_stop_and_start_after_lost),
  };
  return cmocka_run_group_tests(tests, setup_rig, teardown_rig);
}
