// Scenes and rendering shared by the rack-wall detection tests
// (test_rack_detection.cpp, test_rack_cables.cpp): a depth frame rendered
// with its estimator cloud, a flat wall, and that wall with a 0.55 m ISS
// handrail on a seat track.
#pragma once

#include <cstdint>
#include <vector>

#include "common/frame_convert.hpp"
#include "estimator/handrail_detector.hpp"
#include "sim_hal/ground_truth.hpp"
#include "sim_hal/scenario.hpp"
#include "sim_hal/tof_sensor.hpp"

namespace racktest {

struct Rendered {
  std::vector<hal::DepthPoint> points;
  std::vector<estimator::CloudPoint> buffer;
  estimator::OrganizedCloud cloud;
  sim_hal::FrameTruth truth;
};

// The scene from T_world_cam through the depth renderer (sensor seed 7).
inline void render_scene(const sim_hal::Scene& scene, const Eigen::Isometry3d& T_world_cam,
                         std::size_t f, Rendered* r) {
  const sim_hal::CameraIntrinsics cam = sim_hal::pico_flexx_intrinsics();
  sim_hal::DepthRenderer renderer(cam, sim_hal::ToFSettings{});
  renderer.render(scene, T_world_cam, 7, f, &r->points);
  const hal::DepthFrame frame{f, static_cast<std::int64_t>(f) * 200000, cam.width, cam.height,
                              r->points.data()};
  r->cloud = tools::to_estimator_cloud(frame, &r->buffer);
}

// A flat wall (x = 0, facing +x, z up), 4 x 3 m.
inline sim_hal::Scene flat_wall_scene() {
  sim_hal::Scene s;
  s.add_wall(Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitZ(), 4.0, 3.0);
  return s;
}

// That wall with a 0.55 m ISS handrail along y on a seat track (2.6 cm
// wide, 1.3 cm proud) that runs on 15 cm past both its ends.
inline sim_hal::Scene rail_on_seat_track_scene() {
  sim_hal::Scene s = flat_wall_scene();
  constexpr double kTrackProud_m = 0.013, kTrackWidth_m = 0.026;
  s.add_box(Eigen::Vector3d(0.5 * kTrackProud_m, 0.0, 0.0), Eigen::Matrix3d::Identity(),
            Eigen::Vector3d(kTrackProud_m, 0.55 + 0.30, kTrackWidth_m));
  sim_hal::Handrail rail;
  rail.kind = sim_hal::HandrailKind::kIss;
  rail.axis = Eigen::Vector3d::UnitY();
  rail.foot_center = Eigen::Vector3d(kTrackProud_m, 0.0, 0.0);
  s.add_handrail(rail);
  return s;
}

}  // namespace racktest
