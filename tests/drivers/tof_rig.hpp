#pragma once
// The raw path for the ToF tests: the simulator's raw-frame renderer with
// a unit's calibration, that calibration written to a file and read back
// the way the robot reads it, and the robot's processing; plus flat walls
// and the error statistics against the renderer's exact ranges.
#include <unistd.h>
#include <cmath>
#include <cstdio>
#include <string>

#include "sim_hal/scenario.hpp"
#include "sim_hal/tof_raw_renderer.hpp"
#include "tof/calibration_io.hpp"
#include "tof/processor.hpp"

namespace tof_rig {

// A wall facing the camera (camera at the origin looking along world -x),
// turned by tilt_deg about the vertical.
inline sim_hal::Scene wall_scene(double distance_m, double tilt_deg = 0.0,
                                 double reflectivity = 0.6) {
  sim_hal::Scene scene;
  const double t = tilt_deg * M_PI / 180.0;
  scene.add_wall(Eigen::Vector3d(-distance_m, 0, 0), Eigen::Vector3d(std::cos(t), std::sin(t), 0),
                 Eigen::Vector3d(0, 0, 1), 40.0, 40.0, reflectivity);
  return scene;
}

inline Eigen::Isometry3d looking_at_wall() {
  return sim_hal::camera_pose(Eigen::Vector3d::Zero(), Eigen::Vector3d(-1, 0, 0),
                              Eigen::Vector3d(0, 0, 1), Eigen::Vector3d::Zero());
}

// The use cases the tests run: the slowest MODE_9 and the fastest MODE_5.
struct UseCase {
  const char* name;
  tof::Mode mode;
  std::uint32_t max_exposure_us;
};
constexpr UseCase kMode9_5fps{"MODE_9_5FPS_2000", tof::Mode::kMode9, 2000};
constexpr UseCase kMode5_45fps{"MODE_5_45FPS_500", tof::Mode::kMode5, 500};

struct Rig {
  explicit Rig(const sim_hal::RawRenderSettings& settings = {}, std::uint64_t camera_seed = 7)
      : truth(sim_hal::simulated_calibration(sim_hal::pico_flexx_intrinsics(), camera_seed)),
        renderer(sim_hal::pico_flexx_intrinsics(), sim_hal::ToFSettings{}, settings, truth),
        processor(read_back(truth), tof::ProcessingConfig{}) {}

  // The calibration through its file, as the robot would get it.
  static tof::Calibration read_back(const tof::Calibration& cal) {
    char path[] = "/tmp/tof_rig_calXXXXXX";
    const int fd = mkstemp(path);
    if (fd >= 0) close(fd);
    std::string error;
    tof::Calibration loaded;
    if (!tof::write_calibration_file(path, cal, &error) ||
        !tof::load_calibration_file(path, &loaded, &error)) {
      std::fprintf(stderr, "calibration file: %s\n", error.c_str());
    }
    std::remove(path);
    return loaded;
  }

  // Renders and processes one frame; false when processing fails.
  bool capture(const sim_hal::Scene& scene, const UseCase& uc, std::uint64_t frame) {
    renderer.render(scene, looking_at_wall(), uc.mode, uc.max_exposure_us, 11, frame, &raw);
    return processor.process(raw, &depth) == tof::ProcessStatus::kOk;
  }

  tof::Calibration truth;
  sim_hal::RawRenderer renderer;
  tof::Processor processor;
  tof::RawFrame raw;
  hal::DepthFrame depth;
};

// Errors of the valid pixels against the exact ranges, pooled over frames.
struct Stats {
  double sum = 0.0, sum2 = 0.0, reported_noise = 0.0;
  long valid = 0, pixels = 0, wrong_unwrap = 0;
  void add(const Rig& rig, double wrong_m = 0.3) {
    const float* r = rig.processor.range_m();
    const std::vector<float>& truth = rig.renderer.true_range_m();
    for (std::size_t i = 0; i < tof::kPixels; ++i) {
      ++pixels;
      if (r[i] <= 0.0f || truth[i] <= 0.0f) continue;
      const double e = r[i] - truth[i];
      if (std::fabs(e) > wrong_m) {
        ++wrong_unwrap;
        continue;
      }
      ++valid;
      sum += e;
      sum2 += e * e;
      reported_noise += rig.depth.points[i].noise_m;
    }
  }
  double bias_m() const { return valid ? sum / valid : 0.0; }
  double noise_m() const {
    return valid ? std::sqrt(std::max(0.0, sum2 / valid - bias_m() * bias_m())) : 0.0;
  }
  double valid_fraction() const { return pixels ? static_cast<double>(valid) / pixels : 0.0; }
  double mean_reported_noise_m() const { return valid ? reported_noise / valid : 0.0; }
};

}  // namespace tof_rig
