#include "estimator/mount_beside.hpp"

#include <Eigen/Geometry>
#include <cmath>

namespace estimator {

namespace {
// The pixels' noise widens the level's tolerance by twice its sigma, up to
// this (at 1.5 m the depth renderer's sigma is near a centimetre).
constexpr float kMaxNoiseWidening_m = 0.01f;
}  // namespace

MountBeside measure_mount_beside(const OrganizedCloud& cloud, const DetectorConfig& cfg,
                                 const Workspace& ws, const Plane& wall, const CenterLine& line,
                                 float mount_above_wall_m) {
  MountBeside m;
  const Eigen::Vector3f& n = wall.normal;
  const Eigen::Vector3f& a = line.axis;
  const Eigen::Vector3f across = a.cross(n);
  const float foot_m = mount_above_wall_m - cfg.mount_step_m;  // a seat track's foot
  for (std::int32_t i : ws.sample) {
    const CloudPoint& q = cloud.points[i];
    const Eigen::Vector3f p(q.x_m, q.y_m, q.z_m);
    const Eigen::Vector3f r = p - line.point;
    const float t = r.dot(a);
    if (t < line.t_min_m || t > line.t_max_m) continue;
    const float u = r.dot(across);
    const float u_abs = std::fabs(u);
    if (u_abs < cfg.mount_beside_min_m || u_abs > cfg.mount_beside_max_m) continue;
    const int side = u > 0.0f ? 1 : 0;
    ++m.band_pixels[side];
    const float noise = q.noise_m > 0.0f && q.noise_m < 0.05f ? q.noise_m : 0.0f;
    const float tolerance =
        cfg.mount_beside_tolerance_m + std::fmin(2.0f * noise, kMaxNoiseWidening_m);
    const float h = wall.signed_distance(p);
    if (std::fabs(h - mount_above_wall_m) <= tolerance || std::fabs(h - foot_m) <= tolerance) {
      ++m.at_mount[side];
    }
  }
  return m;
}

bool mount_shows_beside(const MountBeside& m, const DetectorConfig& cfg) {
  bool judged = false;
  for (int side = 0; side < 2; ++side) {
    if (m.band_pixels[side] < cfg.mount_beside_min_pixels) continue;
    judged = true;
    if (static_cast<float>(m.at_mount[side]) >=
        cfg.mount_beside_min_fraction * static_cast<float>(m.band_pixels[side])) {
      return true;
    }
  }
  return !judged;
}

}  // namespace estimator
