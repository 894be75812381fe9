#pragma once
// The rig the Pico Flexx USB driver's tests share: one emulated camera
// (sim_hal/emulated_pico_flexx.hpp) under umockdev sending a test pattern,
// a listener that checks every frame against it, and the driver's settings
// the tests start from. umockdev allows only a few dozen descriptors per
// process, so one emulated device serves every test of an executable (the
// group's setup and teardown), and the tests run in their listed order.
//
// Include it in exactly one file of a test executable: it brings the
// allocation counter, which replaces the global allocation functions.
#include <atomic>
#include <chrono>
#include <cstdio>
#include <memory>
#include <string>
#include <thread>

#include "allocation_counter.hpp"
#include "cmocka_cpp.hpp"
#include "pico_flexx/usb_camera.hpp"
#include "sim_hal/emulated_pico_flexx.hpp"

namespace usb_camera_rig {

// Every sample of a frame's images is a function of its sequence number
// and position, so a delivered frame can be checked sample by sample.
inline std::uint16_t expected_sample(std::uint64_t sequence, std::size_t index) {
  return static_cast<std::uint16_t>((sequence * 131u + index * 7u) & 0xFFFu);
}

class PatternSource final : public sim_hal::RawFrameSource {
 public:
  void fill(std::uint64_t frame_index, std::int64_t, const hal::UseCase& use_case,
            std::uint32_t exposure_us, tof::RawFrame* out) override {
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
inline Rig* g_rig = nullptr;

inline pico_flexx::UsbCameraConfig default_config() {
  pico_flexx::UsbCameraConfig c;
  c.use_case_index = 5;  // MODE_5_45FPS_500
  // Every emulated URB is a round trip between this thread and umockdev's,
  // which on a loaded two-core machine can take milliseconds: fewer,
  // larger transfers (a MODE_5 frame in one) keep the stream ahead.
  c.transfer_bytes = 512 * 1024;
  c.transfer_count = 4;
  return c;
}

inline void sleep_ms(int ms) {
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

// Streams until `frames` more frames have arrived (bounded); true if they did.
inline bool frames_arrive(const CheckingListener& listener, long frames, int timeout_ms) {
  const long target = listener.frames.load() + frames;
  return wait_for([&] { return listener.frames.load() >= target; }, timeout_ms);
}

// The group's setup: the emulated camera, with a calibration "file" of
// 10 kB (three chunks, the last a partial one).
inline int setup_rig(void**) {
  g_rig = new Rig;
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

inline int teardown_rig(void**) {
  delete g_rig;
  g_rig = nullptr;
  return 0;
}

}  // namespace usb_camera_rig
