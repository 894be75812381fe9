// End to end through USB: the simulated world rendered into raw frames by
// the emulated camera (sim_hal/rendered_frame_source.hpp), read through
// real libusb by the driver, processed by the robot's ToF pipeline with the
// calibration read from the camera, delivered by hal::DepthCamera. A wall
// 1 m away must come out 1 m away. Then the camera is lost (unplugged past
// the reconnect window) and the capture stopped and started again in the
// same process.
#include <algorithm>
#include <atomic>
#include <chrono>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "cmocka_cpp.hpp"
#include "pico_flexx/usb_depth_camera.hpp"
#include "sim_hal/rendered_frame_source.hpp"
#include "sim_hal/umockdev_preload.hpp"
#include "tof/calibration_io.hpp"

namespace {

struct FixedPose final : sim_hal::CameraPoseSource {
  Eigen::Isometry3d T_world_cam(std::int64_t) override {
    return sim_hal::camera_pose(Eigen::Vector3d::Zero(), Eigen::Vector3d(-1, 0, 0),
                                Eigen::Vector3d(0, 0, 1), Eigen::Vector3d::Zero());
  }
};

// Keeps the centre pixels' depth of every frame.
struct DepthListener final : hal::DepthDataListener {
  void on_new_data(const hal::DepthFrame& frame) override {
    std::lock_guard<std::mutex> lock(mutex);
    ++frames;
    valid_share = static_cast<double>(hal::count_valid(frame)) / (frame.width * frame.height);
    const hal::DepthPoint& p = frame.at(frame.height / 2, frame.width / 2);
    if (hal::is_valid(p)) centre_z_m.push_back(p.z_m);
  }
  std::mutex mutex;
  long count() {
    std::lock_guard<std::mutex> lock(mutex);
    return frames;
  }
  long frames = 0;
  double valid_share = 0.0;
  std::vector<float> centre_z_m;
};

// Waits (bounded) for `done`; true when it happened.
template <typename F>
bool wait_for(F done, int timeout_ms) {
  for (int waited_ms = 0; waited_ms < timeout_ms; waited_ms += 20) {
    if (done()) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return done();
}

// The camera lost while capturing, the capture stopped, started while the
// camera is away (DISCONNECTED, as royale), and started again once it is
// back: frames flow, no restart needed.
void check_stop_and_start_after_lost(pico_flexx::UsbDepthCamera& camera,
                                     sim_hal::EmulatedPicoFlexx& emulated,
                                     DepthListener& listener) {
  assert_int_equal(camera.start_capture(), hal::CameraStatus::kSuccess);
  const long before = listener.count();
  assert_true(wait_for([&] { return listener.count() >= before + 2; }, 20000));
  emulated.unplug();
  assert_true(
      wait_for([&] { return camera.usb().state() == pico_flexx::CameraState::kLost; }, 5000));
  assert_false(camera.is_connected());
  assert_true(camera.is_capturing());  // wanted, and being brought back
  assert_int_equal(camera.stop_capture(), hal::CameraStatus::kSuccess);
  assert_false(camera.is_capturing());
  assert_int_equal(camera.start_capture(), hal::CameraStatus::kDisconnected);
  std::string error;
  assert_true(emulated.replug(&error));
  assert_true(wait_for([&] { return camera.is_connected(); }, 5000));
  assert_int_equal(camera.start_capture(), hal::CameraStatus::kSuccess);
  const long again = listener.count();
  assert_true(wait_for([&] { return listener.count() >= again + 3; }, 20000));
  assert_int_equal(camera.stop_capture(), hal::CameraStatus::kSuccess);
  std::printf("lost, stopped and started again: %ld depth frames after the replug\n",
              listener.count() - again);
}

void test_wall_through_usb(void**) {
  hal::MonotonicClock clock;
  sim_hal::Scene scene;
  scene.add_wall(Eigen::Vector3d(-1.0, 0, 0), Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(0, 0, 1),
                 40.0, 40.0, 0.6);
  const tof::Calibration truth =
      sim_hal::simulated_calibration(sim_hal::pico_flexx_intrinsics(), 7);
  sim_hal::RawRenderer renderer(sim_hal::pico_flexx_intrinsics(), sim_hal::ToFSettings{},
                                sim_hal::RawRenderSettings{}, truth);
  FixedPose pose;
  sim_hal::RenderedFrameSource source(scene, pose, renderer, 11);
  sim_hal::EmulatedCameraConfig config;
  config.calibration = tof::calibration_to_json(truth);
  std::string error;
  auto emulated = sim_hal::EmulatedPicoFlexx::create(config, &source, clock, &error);
  if (!emulated) fail_msg("%s", error.c_str());

  pico_flexx::UsbCameraConfig usb;
  usb.use_case_index = 0;  // MODE_9_5FPS_2000: two frequencies, unwrapped
  usb.reconnect_window_ms = 500;
  pico_flexx::UsbDepthCamera camera(usb, pico_flexx::PipelineConfig{}, clock);
  const hal::CameraStatus init = camera.initialize();
  if (init != hal::CameraStatus::kSuccess) fail_msg("initialize: %s", camera.error().c_str());
  const hal::UseCase* use_case = nullptr;
  assert_int_equal(camera.current_use_case(&use_case), hal::CameraStatus::kSuccess);
  assert_string_equal(use_case->name, "MODE_9_5FPS_2000");
  hal::LensParameters lens;
  assert_int_equal(camera.lens_parameters(&lens), hal::CameraStatus::kSuccess);
  assert_near(lens.fx_px, truth.lens.fx_px, 1e-9);  // the camera's calibration, read over USB
  assert_int_equal(camera.set_use_case("MODE_7_NONE"), hal::CameraStatus::kUseCaseNotSupported);

  DepthListener listener;
  assert_int_equal(camera.register_data_listener(&listener), hal::CameraStatus::kSuccess);
  assert_int_equal(camera.start_capture(), hal::CameraStatus::kSuccess);
  assert_true(camera.is_capturing());
  for (int waited_ms = 0; waited_ms < 20000; waited_ms += 50) {
    {
      std::lock_guard<std::mutex> lock(listener.mutex);
      if (listener.frames >= 8) break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  assert_int_equal(camera.stop_capture(), hal::CameraStatus::kSuccess);
  std::unique_lock<std::mutex> lock(listener.mutex);
  std::printf("wall at 1 m through USB: %ld depth frames, %.1f %% valid, %zu centre depths\n",
              listener.frames, 100.0 * listener.valid_share, listener.centre_z_m.size());
  assert_true(listener.frames >= 8);
  assert_true(listener.valid_share > 0.95);
  std::vector<float> z = listener.centre_z_m;
  assert_true(z.size() >= 6);
  std::nth_element(z.begin(), z.begin() + z.size() / 2, z.end());
  assert_near(z[z.size() / 2], 1.0, 0.01);
  const pico_flexx::UsbCounters c = camera.usb().counters();
  assert_int_equal(c.assembly.dropped(), 0);
  assert_int_equal(camera.pipeline()->counts().frames_dropped, 0);
  lock.unlock();
  check_stop_and_start_after_lost(camera, *emulated, listener);
}

}  // namespace

int main(int, char** argv) {
  sim_hal::umockdev_preload::ensure(argv);
  const struct CMUnitTest tests[] = {cmocka_unit_test(test_wall_through_usb)};
  return cmocka_run_group_tests(tests, nullptr, nullptr);
}
