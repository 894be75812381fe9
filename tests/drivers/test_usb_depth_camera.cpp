// End to end through USB: the simulated world rendered into raw frames by
// the emulated camera (sim_hal/rendered_frame_source.hpp), read through
// real libusb by the driver, processed by the robot's ToF pipeline with the
// calibration read from the camera, delivered by hal::DepthCamera. A wall
// 1 m away must come out 1 m away.
#include <algorithm>
#include <atomic>
#include <chrono>
#include <mutex>
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
  long frames = 0;
  double valid_share = 0.0;
  std::vector<float> centre_z_m;
};

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
  sim_hal::RenderedFrameSource source(scene, pose, renderer, clock, 11);
  sim_hal::EmulatedCameraConfig config;
  config.calibration = tof::calibration_to_json(truth);
  std::string error;
  auto emulated = sim_hal::EmulatedPicoFlexx::create(config, &source, clock, &error);
  if (!emulated) fail_msg("%s", error.c_str());

  pico_flexx::UsbCameraConfig usb;
  usb.use_case_index = 0;  // MODE_9_5FPS_2000: two frequencies, unwrapped
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
  std::lock_guard<std::mutex> lock(listener.mutex);
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
}

}  // namespace

int main(int, char** argv) {
  sim_hal::umockdev_preload::ensure(argv);
  const struct CMUnitTest tests[] = {cmocka_unit_test(test_wall_through_usb)};
  return cmocka_run_group_tests(tests, nullptr, nullptr);
}
