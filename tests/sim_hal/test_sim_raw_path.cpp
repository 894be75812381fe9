// The simulated camera on the raw path: the raw renderer's
// phase frames through the robot's ToF processing, on the calibration file
// the simulated unit wrote. On a flat wall its points match the depth
// renderer's within their noise; the tamper still reaches the frames; and
// a frame costs no allocation once the camera runs.
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "allocation_counter.hpp"
#include "cmocka_cpp.hpp"
#include "sim_hal/simulated_camera.hpp"

namespace {

// A 3 x 3 m wall 0.8 m in front of the camera, filling the view.
const char* kScenario = R"({
  "name": "raw-wall", "seed": 9,
  "scene": {"walls": [{"center": [0, 0, 0], "normal": [1, 0, 0], "size": [3, 3]}]},
  "poses": [{"position": [0.8, 0, 0], "frames": 6}]
})";

sim_hal::Scenario load() {
  sim_hal::Scenario s;
  std::string error;
  assert_true(sim_hal::parse_scenario(kScenario, "raw-wall.json", &s, &error));
  return s;
}

// Keeps a copy of the last frame (lock-step: on the test's thread).
class Copy final : public hal::DepthDataListener {
 public:
  Copy() { points.reserve(tof::kPixels); }
  void on_new_data(const hal::DepthFrame& frame) override {
    points.assign(frame.points,
                  frame.points + static_cast<std::size_t>(frame.width) * frame.height);
    ++frames;
  }
  std::vector<hal::DepthPoint> points;
  int frames = 0;
};

// A camera on MODE_9_5FPS_2000, on the raw path when `pipeline` is given.
struct Camera {
  Camera(const sim_hal::Scenario& s, const hal::Clock& clock)
      : camera(s, clock, sim_hal::SimulatedCamera::Pacing::kAsFastAsPossible) {
    assert_int_equal(static_cast<int>(camera.initialize()), 0);
    assert_int_equal(static_cast<int>(camera.set_use_case("MODE_9_5FPS_2000")), 0);
    assert_int_equal(static_cast<int>(camera.register_data_listener(&copy)), 0);
  }
  // The robot's side: the unit's calibration from the file the camera
  // wrote, the pipeline built on it.
  void use_raw_path(const hal::Clock& clock) {
    const std::string path = "/tmp/hrp_sim_raw_" + std::to_string(getpid()) + ".json";
    std::string error;
    assert_true(camera.write_unit_calibration(path, &error));
    pipeline = pico_flexx::open_raw_depth_pipeline(path, {}, clock, &error);
    std::remove(path.c_str());
    if (!pipeline) print_error("%s\n", error.c_str());
    assert_non_null(pipeline.get());
    assert_int_equal(static_cast<int>(camera.set_raw_pipeline(pipeline.get())), 0);
    assert_true(camera.raw_path());
  }
  sim_hal::SimulatedCamera camera;
  Copy copy;
  std::unique_ptr<pico_flexx::RawDepthPipeline> pipeline;
};

double range_m(const hal::DepthPoint& p) {
  return std::sqrt(static_cast<double>(p.x_m) * p.x_m + static_cast<double>(p.y_m) * p.y_m +
                   static_cast<double>(p.z_m) * p.z_m);
}

void test_flat_wall_matches_the_depth_renderer(void**) {
  const sim_hal::Scenario s = load();
  hal::ManualClock clock;
  Camera depth(s, clock), raw(s, clock);
  raw.use_raw_path(clock);
  long both = 0, depth_valid = 0, raw_valid = 0, outside = 0, gray_zero = 0;
  double sum = 0.0, sum_sigma = 0.0;
  for (int f = 0; f < 6; ++f) {
    assert_int_equal(static_cast<int>(depth.camera.capture_next()), 0);
    assert_int_equal(static_cast<int>(raw.camera.capture_next()), 0);
    assert_int_equal(raw.copy.frames, f + 1);
    for (std::size_t i = 0; i < tof::kPixels; ++i) {
      const hal::DepthPoint& d = depth.copy.points[i];
      const hal::DepthPoint& r = raw.copy.points[i];
      const bool dv = hal::is_valid(d), rv = hal::is_valid(r);
      depth_valid += dv;
      raw_valid += rv;
      if (rv && r.gray_value == 0) ++gray_zero;
      if (!dv || !rv) continue;
      ++both;
      // The same ray: the points differ along it by the two noises.
      const double diff = range_m(r) - range_m(d);
      const double sigma = std::sqrt(static_cast<double>(r.noise_m) * r.noise_m +
                                     static_cast<double>(d.noise_m) * d.noise_m);
      const double across =
          std::hypot(r.x_m / r.z_m - d.x_m / d.z_m, r.y_m / r.z_m - d.y_m / d.z_m);
      if (across > 1e-4) ++outside;  // a different ray: the lenses disagree
      sum += diff;
      sum_sigma += sigma;
      if (std::fabs(diff) > 5.0 * sigma) ++outside;
    }
  }
  const double mean_mm = 1e3 * sum / static_cast<double>(both);
  std::printf(
      "flat wall at 0.8 m, 6 frames: %ld pixels valid in both (depth %ld, raw %ld); mean "
      "raw - depth %+.2f mm, mean combined sigma %.2f mm, %ld beyond 5 sigma\n",
      both, depth_valid, raw_valid, mean_mm, 1e3 * sum_sigma / static_cast<double>(both), outside);
  assert_true(both > 6L * static_cast<long>(tof::kPixels) * 9 / 10);
  assert_true(raw_valid >= depth_valid * 95 / 100);
  assert_true(std::fabs(mean_mm) < 2.0);
  assert_true(outside < both / 1000);
  assert_int_equal(gray_zero, 0);  // the processing's amplitude reaches the grey plane
  const pico_flexx::PipelineCounts c = raw.pipeline->counts();
  assert_int_equal(c.frames_in, 6);
  assert_int_equal(c.frames_dropped, 0);
  assert_int_equal(c.frames_mostly_invalid, 0);
  assert_true(raw.pipeline->processing_median_us() >= 0);
}

// Occludes every frame: the points arrive zeroed on the raw path too.
class Blind final : public sim_hal::FrameTamper {
 public:
  void tamper(std::int64_t, hal::DepthFrame*, std::vector<hal::DepthPoint>* points) override {
    for (hal::DepthPoint& p : *points) p = hal::DepthPoint{};
  }
};

void test_tamper_reaches_raw_path_frames(void**) {
  const sim_hal::Scenario s = load();
  hal::ManualClock clock;
  Camera raw(s, clock);
  Blind blind;
  raw.camera.set_tamper(&blind);
  raw.use_raw_path(clock);
  assert_int_equal(static_cast<int>(raw.camera.capture_next()), 0);
  const hal::DepthFrame frame{0, 0, 224, 171, raw.copy.points.data()};
  assert_int_equal(hal::count_valid(frame), 0);
  assert_int_equal(raw.pipeline->counts().frames_delivered, 1);
}

void test_no_allocation_per_frame(void**) {
  const sim_hal::Scenario s = load();
  hal::ManualClock clock;
  Camera raw(s, clock);
  raw.use_raw_path(clock);
  assert_int_equal(static_cast<int>(raw.camera.capture_next()), 0);  // warm up
  alloc_counter::arm();
  for (int f = 1; f < 6; ++f) {
    clock.advance_us(200000);
    if (raw.camera.capture_next() != hal::CameraStatus::kSuccess) break;
  }
  const long allocations = alloc_counter::disarm();
  if (allocations != 0) print_error("%ld allocations over 5 raw-path frames\n", allocations);
  assert_int_equal(allocations, 0);
  assert_int_equal(raw.copy.frames, 6);
}

}  // namespace

int main() {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_flat_wall_matches_the_depth_renderer),
      cmocka_unit_test(test_tamper_reaches_raw_path_frames),
      cmocka_unit_test(test_no_allocation_per_frame),
  };
  return cmocka_run_group_tests(tests, nullptr, nullptr);
}
