#pragma once
// The emulated Pico Flexx (umockdev, in this process) looking at a wall 1 m
// ahead, rendered with the simulator's raw renderer and a simulated unit's
// calibration: the rig the royale tests share. The process must run under
// umockdev's preload library (sim_hal::umockdev_preload::ensure).
#include <memory>
#include <string>

#include "sim_hal/rendered_frame_source.hpp"
#include "tof/calibration_io.hpp"

namespace testing_support {

struct FixedWallPose final : sim_hal::CameraPoseSource {
  Eigen::Isometry3d T_world_cam(std::int64_t) override {
    return sim_hal::camera_pose(Eigen::Vector3d::Zero(), Eigen::Vector3d(-1, 0, 0),
                                Eigen::Vector3d(0, 0, 1), Eigen::Vector3d::Zero());
  }
};

struct EmulatedWallRig {
  hal::MonotonicClock clock;
  sim_hal::Scene scene;
  tof::Calibration truth = sim_hal::simulated_calibration(sim_hal::pico_flexx_intrinsics(), 7);
  sim_hal::RawRenderer renderer{sim_hal::pico_flexx_intrinsics(), sim_hal::ToFSettings{},
                                sim_hal::RawRenderSettings{}, truth};
  FixedWallPose pose;
  std::unique_ptr<sim_hal::RenderedFrameSource> source;
  sim_hal::EmulatedCameraConfig config;
  std::unique_ptr<sim_hal::EmulatedPicoFlexx> camera;

  // Builds the wall and plugs the camera in; false with *error saying why.
  bool plug_in(std::string* error) {
    scene.add_wall(Eigen::Vector3d(-1.0, 0, 0), Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(0, 0, 1),
                   40.0, 40.0, 0.6);
    source = std::make_unique<sim_hal::RenderedFrameSource>(scene, pose, renderer, 11);
    config.calibration = tof::calibration_to_json(truth);
    camera = sim_hal::EmulatedPicoFlexx::create(config, source.get(), clock, error);
    return camera != nullptr;
  }
};

}  // namespace testing_support
