// royale's sample program (drivers/pico_flexx/royale/samples), an
// application of the royale API only, run against the emulated camera (a
// wall 1 m ahead) through real libusb under umockdev's preload library. It
// runs in this process, its main() renamed: the emulated camera serves
// only the process that owns it (its handler reads and writes the host's
// URBs in place). Its output must name the camera, its use cases and
// lens, frames and a centre depth of 1 m; its exit status 0.
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <memory>
#include <mutex>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "royale.hpp"

#define main royale_sample_main
#include "../../drivers/pico_flexx/royale/samples/sample_camera_info.cpp"
#undef main

#include "allocation_counter.hpp"
#include "cmocka_cpp.hpp"
#include "emulated_wall_rig.hpp"
#include "sim_hal/umockdev_preload.hpp"

namespace {

// The number after `key` on its line, or NaN when the line is missing.
double value_after(const std::string& text, const std::string& key) {
  const std::size_t at = text.find(key);
  if (at == std::string::npos) return std::nan("");
  return std::strtod(text.c_str() + at + key.size(), nullptr);
}

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

void test_sample_against_the_emulated_camera(void**) {
  const Rig& rig = *g_rig;
  std::ostringstream captured;
  std::streambuf* const cout = std::cout.rdbuf(captured.rdbuf());
  char name[] = "royale_sample_camera_info";
  char seconds[] = "3";
  char* args[] = {name, seconds, nullptr};
  const int status = royale_sample_main(2, args);
  std::cout.rdbuf(cout);
  const std::string out = captured.str();
  std::printf("%s", out.c_str());
  assert_int_equal(status, 0);

  assert_true(out.find("Detected 1 camera(s).") != std::string::npos);
  assert_true(out.find("Camera ID: " + rig.config.serial) != std::string::npos);
  assert_true(out.find("Camera name: PICOFLEXX") != std::string::npos);
  assert_int_equal(static_cast<int>(value_after(out, "Use cases: ")), 6);
  assert_true(out.find("    MODE_9_5FPS_2000") != std::string::npos);
  // As royale: the first use case offered, after initialize().
  assert_true(out.find("Current use case: MODE_9_5FPS_2000 (5 fps)") != std::string::npos);
  assert_true(out.find("Exposure limits: 1 .. 2000 us") != std::string::npos);
  // The lens from the camera's own calibration, read over USB.
  assert_near(value_after(out, "fx/fy "), rig.truth.lens.fx_px, 0.01);
  // Three seconds at 5 fps, with room for a loaded host (and the sanitizer).
  const double frames = value_after(out, "Frames received: ");
  assert_true(frames >= 8);
  assert_near(value_after(out, "Centre depth: "), 1.0, 0.01);
}

// Keeps what the royale tests check of each frame: the buffers' addresses
// (the same every frame), the exposures; and counts the allocations on the
// camera's thread from the end of frame kArmAt's call to the start of
// frame kDisarmAt's (the copies into DepthData and the processing between).
class RecordingListener final : public royale::IDepthDataListener {
 public:
  static constexpr long kArmAt = 3, kDisarmAt = 9;

  void onNewData(const royale::DepthData* data) override {
    std::lock_guard<std::mutex> lock(mutex);
    if (frames == kDisarmAt) allocations = alloc_counter::disarm();
    if (frames == 0) {
      first_points = data->points.data();
      first_exposures = data->exposureTimes.data();
    }
    moved = moved || data->points.data() != first_points ||
            data->exposureTimes.data() != first_exposures;
    ++frames;
    exposures = data->exposureTimes.size();
    stream_ok = stream_ok && data->streamId == 0xdefa;
    // Since the 1970 epoch, as royale's: within a second of the system
    // clock's now (the capture was moments ago).
    const auto since_capture =
        std::chrono::system_clock::now().time_since_epoch() -
        std::chrono::duration_cast<std::chrono::nanoseconds>(data->timeStamp);
    epoch_ok = epoch_ok && since_capture >= std::chrono::nanoseconds(0) &&
               since_capture < std::chrono::seconds(1);
    size_ok = size_ok && data->points.size() == static_cast<size_t>(data->width) * data->height;
    const royale::DepthPoint& p =
        data->points[static_cast<size_t>(data->height / 2) * data->width + data->width / 2];
    if (p.depthConfidence > 0) {
      centre_sum += p.z;
      ++centre_frames;
    }
    if (frames == kArmAt) alloc_counter::arm();
  }
  long count() {
    std::lock_guard<std::mutex> lock(mutex);
    return frames;
  }
  std::mutex mutex;
  long frames = 0, centre_frames = 0;
  double centre_sum = 0.0;
  std::size_t exposures = 0;
  const void* first_points = nullptr;
  const void* first_exposures = nullptr;
  bool moved = false, size_ok = true, stream_ok = true, epoch_ok = true;
  long allocations = -1;
};

bool wait_for_frames(RecordingListener* listener, long frames) {
  for (int waited_ms = 0; waited_ms < 20000; waited_ms += 50) {
    if (listener->count() >= frames) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  return false;
}

// The API's contract beyond the sample: statuses before initialize, an
// unknown id and use case, a use-case change (two frequencies, two
// exposure times), a capture refused without a listener, no frame after
// unregistering, the frame's buffers reused.
void test_api_contract(void**) {
  using royale::CameraStatus;
  assert_string_equal(royale::getStatusString(CameraStatus::USECASE_NOT_SUPPORTED).c_str(),
                      "USECASE_NOT_SUPPORTED");
  assert_int_equal(static_cast<int>(CameraStatus::DEVICE_NOT_INITIALIZED), 5004);
  assert_int_equal(static_cast<long>(CameraStatus::UNKNOWN), 0x7fffff01L);
  assert_string_equal(royale::getStatusString(CameraStatus::UNKNOWN).c_str(), "UNKNOWN");
  assert_string_equal(royale::getStatusString(CameraStatus::FSM_INVALID_TRANSITION).c_str(),
                      "FSM_INVALID_TRANSITION");
  assert_string_equal(royale::getErrorString(CameraStatus::UNKNOWN).c_str(),
                      "An error of no known kind.");
  royale::CameraManager manager;
  assert_null(manager.createCamera(g_rig->config.serial).get());  // not listed yet
  const royale::Vector<royale::String> ids = manager.getConnectedCameraList();
  assert_int_equal(ids.size(), 1);
  // royale's container calls beside the standard ones.
  assert_int_equal(ids.count(), 1);
  const std::vector<royale::String> as_std = ids.toStdVector();
  assert_string_equal(as_std[0].toStdString().c_str(), g_rig->config.serial.c_str());
  assert_true(royale::String::fromStdString(g_rig->config.serial) == ids[0]);
  assert_true(royale::String::fromCArray(nullptr).empty());
  assert_int_equal(royale::Vector<int>::fromStdVector({1, 2, 3}).count(), 3);
  assert_null(manager.createCamera("0000-0000-0000").get());
  std::unique_ptr<royale::ICameraDevice> device = manager.createCamera(ids[0]);
  assert_non_null(device.get());
  RecordingListener listener;
  assert_int_equal(device->setUseCase("MODE_9_5FPS_2000"), CameraStatus::DEVICE_NOT_INITIALIZED);
  assert_int_equal(device->startCapture(), CameraStatus::DEVICE_NOT_INITIALIZED);
  assert_int_equal(device->initialize(), CameraStatus::SUCCESS);
  assert_int_equal(device->initialize(), CameraStatus::DEVICE_ALREADY_INITIALIZED);
  bool calibrated = false;
  assert_int_equal(device->isCalibrated(calibrated), CameraStatus::SUCCESS);
  assert_true(calibrated);
  assert_int_equal(device->setUseCase("MODE_7_NONE"), CameraStatus::USECASE_NOT_SUPPORTED);
  assert_int_equal(device->setUseCase("MODE_9_10FPS_1000"), CameraStatus::SUCCESS);
  royale::Vector<royale::Pair<royale::String, royale::String>> info;
  assert_int_equal(device->getCameraInfo(info), CameraStatus::SUCCESS);
  assert_int_equal(info.count(), 3);
  assert_string_equal(info[0].first.c_str(), "SERIAL_NUMBER");
  assert_string_equal(info[0].second.c_str(), g_rig->config.serial.c_str());
  assert_string_equal(info[1].second.c_str(), "1.4");  // the emulator's firmware
  royale::Vector<royale::StreamId> streams;
  assert_int_equal(device->getStreams(streams), CameraStatus::SUCCESS);
  assert_int_equal(streams.count(), 1);
  assert_int_equal(streams[0], 0xdefa);
  uint32_t stream_count = 0;
  assert_int_equal(device->getNumberOfStreams("MODE_9_5FPS_2000", stream_count),
                   CameraStatus::SUCCESS);
  assert_int_equal(stream_count, 1);
  assert_int_equal(device->getNumberOfStreams("MODE_7_NONE", stream_count),
                   CameraStatus::USECASE_NOT_SUPPORTED);
  unsigned major = 0, minor = 0, patch = 0, build = 1;
  royale::String revision = "x";
  royale::getVersion(major, minor, patch, build, revision);
  assert_true(major == 3 && minor == 21 && patch == 0 && build == 0 && revision.empty());
  assert_string_equal(royale::getErrorString(CameraStatus::DEVICE_NOT_INITIALIZED).c_str(),
                      "initialize() must succeed before this call.");
  royale::String use_case;
  assert_int_equal(device->getCurrentUseCase(use_case), CameraStatus::SUCCESS);
  assert_string_equal(use_case.c_str(), "MODE_9_10FPS_1000");
  royale::Pair<uint32_t, uint32_t> limits;
  assert_int_equal(device->getExposureLimits(limits), CameraStatus::SUCCESS);
  assert_int_equal(limits.second, 1000);
  assert_int_equal(limits.toStdPair().second, 1000);
  assert_true((royale::Pair<uint32_t, uint32_t>::fromStdPair({1u, 1000u}) == limits));
  assert_int_equal(device->setExposureTime(limits.second + 1),
                   CameraStatus::EXPOSURE_TIME_NOT_SUPPORTED);
  assert_int_equal(device->setExposureTime(800), CameraStatus::SUCCESS);
  assert_int_equal(device->setExposureTime(800, 7), CameraStatus::INVALID_VALUE);
  // The stream's own id names it as well as 0 does.
  assert_int_equal(device->setExposureTime(800, 0xdefa), CameraStatus::SUCCESS);
  assert_int_equal(device->startCapture(), CameraStatus::LOGIC_ERROR);  // no listener
  assert_int_equal(device->registerDataListener(nullptr), CameraStatus::INVALID_VALUE);
  assert_int_equal(device->registerDataListener(&listener), CameraStatus::SUCCESS);
  assert_int_equal(device->startCapture(), CameraStatus::SUCCESS);
  bool capturing = false;
  assert_int_equal(device->isCapturing(capturing), CameraStatus::SUCCESS);
  assert_true(capturing);
  assert_true(wait_for_frames(&listener, 12));
  assert_int_equal(device->unregisterDataListener(), CameraStatus::SUCCESS);
  const long at_unregister = listener.count();
  std::this_thread::sleep_for(std::chrono::milliseconds(300));  // three frame periods
  assert_int_equal(listener.count(), at_unregister);
  assert_int_equal(device->stopCapture(), CameraStatus::SUCCESS);
  assert_int_equal(device->stopCapture(), CameraStatus::SUCCESS);  // not capturing: nothing to do
  std::lock_guard<std::mutex> lock(listener.mutex);
  std::printf(
      "royale API, MODE_9_10FPS_1000: %ld frames, centre %.4f m over %ld; %ld allocations on "
      "the camera's thread over %ld frames\n",
      listener.frames, listener.centre_sum / listener.centre_frames, listener.centre_frames,
      listener.allocations, RecordingListener::kDisarmAt - RecordingListener::kArmAt);
  assert_false(listener.moved);
  assert_true(listener.size_ok);
  assert_true(listener.stream_ok);
  assert_true(listener.epoch_ok);
  assert_int_equal(listener.exposures, 2);
  assert_true(listener.centre_frames > 6);
  assert_near(listener.centre_sum / listener.centre_frames, 1.0, 0.01);
  assert_true(listener.allocations >= 0);  // the window closed
#if defined(__SANITIZE_ADDRESS__)
  // Only operator new is counted here: none on the camera's thread, the
  // DepthData copies and the processing included.
  assert_int_equal(listener.allocations, 0);
#endif
  // Outside the sanitizer malloc is counted too, and libusb's Linux backend
  // callocs each submitted transfer's URB array (about 11 a MODE_9 frame
  // in 64 KB transfers): drivers_usb_camera_streaming checks that bound,
  // with the driver's transfer count.
}

// Keeps the capture time of every frame handed on.
class StampListener final : public royale::IDepthDataListener {
 public:
  void onNewData(const royale::DepthData* data) override {
    std::lock_guard<std::mutex> lock(mutex);
    if (stamps_us.size() < stamps_us.capacity()) stamps_us.push_back(data->timeStamp.count());
  }
  std::mutex mutex;
  std::vector<long long> stamps_us;
};

// setFrameRate below the use case's own: the device hands on one frame per
// 1/rate (the camera keeps its rate, the others are skipped); 0 and rates
// above the use case's are refused; a new use case starts at its own rate.
// Level 1 only: a level-2 call is refused for want of privileges.
void test_frame_rate_and_access_level(void**) {
  using royale::CameraStatus;
  royale::CameraManager manager;
  const royale::Vector<royale::String> ids = manager.getConnectedCameraList();
  assert_int_equal(ids.size(), 1);
  std::unique_ptr<royale::ICameraDevice> device = manager.createCamera(ids[0]);
  assert_non_null(device.get());
  assert_int_equal(device->setFrameRate(4), CameraStatus::DEVICE_NOT_INITIALIZED);
  assert_int_equal(device->initialize(), CameraStatus::SUCCESS);
  royale::CameraAccessLevel level = royale::CameraAccessLevel::L4;
  assert_int_equal(device->getAccessLevel(level), CameraStatus::SUCCESS);
  assert_true(level == royale::CameraAccessLevel::L1);
  assert_int_equal(device->setExposureTimes(royale::Vector<uint32_t>::fromStdVector({500})),
                   CameraStatus::INSUFFICIENT_PRIVILEGES);
  assert_int_equal(device->setUseCase("MODE_9_10FPS_1000"), CameraStatus::SUCCESS);
  uint16_t rate = 0;
  assert_int_equal(device->getMaxFrameRate(rate), CameraStatus::SUCCESS);
  assert_int_equal(rate, 10);
  assert_int_equal(device->getFrameRate(rate), CameraStatus::SUCCESS);
  assert_int_equal(rate, 10);
  assert_int_equal(device->setFrameRate(0), CameraStatus::FRAMERATE_NOT_SUPPORTED);
  assert_int_equal(device->setFrameRate(11), CameraStatus::FRAMERATE_NOT_SUPPORTED);
  assert_int_equal(device->setFrameRate(4), CameraStatus::SUCCESS);
  assert_int_equal(device->getFrameRate(rate), CameraStatus::SUCCESS);
  assert_int_equal(rate, 4);
  StampListener listener;
  listener.stamps_us.reserve(200);
  assert_int_equal(device->registerDataListener(&listener), CameraStatus::SUCCESS);
  assert_int_equal(device->startCapture(), CameraStatus::SUCCESS);
  std::this_thread::sleep_for(std::chrono::milliseconds(3000));
  assert_int_equal(device->stopCapture(), CameraStatus::SUCCESS);
  std::vector<long long> stamps;
  {
    std::lock_guard<std::mutex> lock(listener.mutex);
    stamps = listener.stamps_us;
  }
  assert_true(stamps.size() >= 3);
  long long min_gap_us = 1LL << 40;
  for (std::size_t i = 1; i < stamps.size(); ++i) {
    min_gap_us = std::min(min_gap_us, stamps[i] - stamps[i - 1]);
  }
  const double rate_hz = 1e6 * static_cast<double>(stamps.size() - 1) /
                         static_cast<double>(stamps.back() - stamps.front());
  std::printf(
      "setFrameRate(4) on MODE_9_10FPS_1000: %zu frames in 3 s, %.2f per second between the "
      "first and last, closest two %.0f ms apart\n",
      stamps.size(), rate_hz, 1e-3 * static_cast<double>(min_gap_us));
  assert_true(rate_hz > 3.5 && rate_hz < 4.5);
  assert_true(min_gap_us >= 180000);  // the camera's 100 ms frames, every second or third
  assert_int_equal(device->setUseCase("MODE_9_5FPS_2000"), CameraStatus::SUCCESS);
  assert_int_equal(device->getFrameRate(rate), CameraStatus::SUCCESS);
  assert_int_equal(rate, 5);
}

bool wait_for_flag(const std::atomic<bool>& flag, int timeout_ms) {
  for (int waited = 0; waited < timeout_ms && !flag.load(); waited += 10) {
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return flag.load();
}

// Keeps the events a device reports, in order.
class EventLog final : public royale::IEventListener {
 public:
  struct Entry {
    royale::EventSeverity severity;
    royale::EventType type;
    std::string text;
  };
  void onEvent(std::unique_ptr<royale::IEvent>&& event) override {
    {
      std::lock_guard<std::mutex> lock(mutex);
      entries.push_back({event->severity(), event->type(), event->describe()});
    }
    // From within its own call, as an application may on a lost camera.
    if (event->type() == royale::EventType::ROYALE_DEVICE_DISCONNECTED && device != nullptr) {
      unregistered = device->unregisterEventListener() == royale::CameraStatus::SUCCESS;
    }
  }
  // How many of `type` (and `severity`, unless any) arrived.
  int count(royale::EventType type, int severity = -1) {
    std::lock_guard<std::mutex> lock(mutex);
    int n = 0;
    for (const Entry& e : entries) {
      n += e.type == type && (severity < 0 || static_cast<int>(e.severity) == severity);
    }
    return n;
  }
  bool wait_for(royale::EventType type, int severity, int n, int timeout_ms) {
    for (int waited = 0; waited < timeout_ms; waited += 50) {
      if (count(type, severity) >= n) return true;
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
    return count(type, severity) >= n;
  }
  std::mutex mutex;
  std::vector<Entry> entries;
  royale::ICameraDevice* device = nullptr;  // unregistered from on a lost camera
  std::atomic<bool> unregistered{false};
};

// Events with the driver's own facts: about once a second of capture the
// stream's frames (INFO when none were dropped, WARNING after corrupt
// frames and while none arrive), and a camera pulled out is reported lost
// (FATAL), once.
void test_events_from_the_driver(void**) {
  using royale::EventSeverity;
  using royale::EventType;
  royale::CameraManager manager;
  const royale::Vector<royale::String> ids = manager.getConnectedCameraList();
  assert_int_equal(ids.count(), 1);
  std::unique_ptr<royale::ICameraDevice> device = manager.createCamera(ids[0]);
  assert_non_null(device.get());
  assert_int_equal(device->initialize(), royale::CameraStatus::SUCCESS);
  RecordingListener frames;
  EventLog events;
  assert_int_equal(device->registerEventListener(nullptr), royale::CameraStatus::INVALID_VALUE);
  assert_int_equal(device->registerEventListener(&events), royale::CameraStatus::SUCCESS);
  assert_int_equal(device->registerDataListener(&frames), royale::CameraStatus::SUCCESS);
  assert_int_equal(device->startCapture(), royale::CameraStatus::SUCCESS);
  const int info = static_cast<int>(EventSeverity::ROYALE_INFO);
  const int warning = static_cast<int>(EventSeverity::ROYALE_WARNING);
  const int fatal = static_cast<int>(EventSeverity::ROYALE_FATAL);
  assert_true(events.wait_for(EventType::ROYALE_RAW_FRAME_STATS, info, 2, 5000));
  g_rig->camera->corrupt_next_frames(3);
  assert_true(events.wait_for(EventType::ROYALE_RAW_FRAME_STATS, warning, 1, 5000));
  // The cable pulled: the driver looks for the camera for 10 s, then
  // declares it lost; the listener unregisters itself from that call, and
  // hears nothing more while the capture stands.
  events.device = device.get();
  g_rig->camera->unplug();
  assert_true(events.wait_for(EventType::ROYALE_DEVICE_DISCONNECTED, fatal, 1, 15000));
  assert_true(wait_for_flag(events.unregistered, 1000));
  const int after_unregister = events.count(EventType::ROYALE_RAW_FRAME_STATS);
  std::this_thread::sleep_for(std::chrono::milliseconds(1500));
  assert_int_equal(events.count(EventType::ROYALE_RAW_FRAME_STATS), after_unregister);
  std::string error;
  assert_true(g_rig->camera->replug(&error));
  assert_int_equal(device->stopCapture(), royale::CameraStatus::SUCCESS);
  std::lock_guard<std::mutex> lock(events.mutex);
  int lost = 0;
  for (const EventLog::Entry& e : events.entries) {
    std::printf("  event %d/%d: %s\n", static_cast<int>(e.severity), static_cast<int>(e.type),
                e.text.c_str());
    lost += e.type == EventType::ROYALE_DEVICE_DISCONNECTED;
  }
  assert_int_equal(lost, 1);  // reported once
  // The three corrupt frames, each counted once.
  bool three_dropped = false;
  for (const EventLog::Entry& e : events.entries) {
    three_dropped = three_dropped || e.text.find(" and 3 dropped") != std::string::npos;
  }
  assert_true(three_dropped);
}

}  // namespace

int main(int, char** argv) {
  sim_hal::umockdev_preload::ensure(argv);
  const struct CMUnitTest tests[] = {cmocka_unit_test(test_sample_against_the_emulated_camera),
                                     cmocka_unit_test(test_api_contract),
                                     cmocka_unit_test(test_frame_rate_and_access_level),
                                     cmocka_unit_test(test_events_from_the_driver)};
  return cmocka_run_group_tests(tests, set_up, tear_down);
}
