#pragma once
// Small analytic scenes for estimator unit tests, with no simulator: a
// pinhole camera looking at a wall, optionally with a round bar on legs-less
// supports or a thin cable, ray-cast exactly. Noise-free unless asked.
#include <cmath>
#include <cstdint>
#include <vector>

#include "estimator/organized_cloud.hpp"

namespace testing_support {

struct Cylinder {
  // Infinite-ish cylinder: a point on its axis, unit axis, radius, and the
  // axial extent [t0, t1] measured from the point.
  double px, py, pz, ax, ay, az, radius, t0, t1;
};

struct SyntheticScene {
  int width = 160, height = 120;
  double f_px = 150.0, cx = 78.5, cy = 61.0;  // off-centre on purpose
  // Wall: n . p + d = 0 with n toward the camera.
  double nx = 0.0, ny = 0.0, nz = -1.0, d = 0.6;
  std::vector<Cylinder> cylinders;
  double noise_m = 0.0;
  std::uint64_t seed = 1;
};

// A vertical (image y) round bar of the paper's size standing `offset_m`
// (centre line) off a fronto-parallel wall at `wall_m`, centred on the
// optical axis, `length_m` long.
inline Cylinder vertical_bar(double wall_m, double offset_m, double length_m,
                             double radius_m = 0.0175, double x_m = 0.0) {
  return {x_m, 0.0, wall_m - offset_m, 0.0, 1.0, 0.0, radius_m, -0.5 * length_m, 0.5 * length_m};
}

inline bool hit_cylinder(const Cylinder& c, const double r[3], double* t_out) {
  const double o[3] = {-c.px, -c.py, -c.pz};  // ray origin (0) minus axis point
  const double a[3] = {c.ax, c.ay, c.az};
  const double od = o[0] * a[0] + o[1] * a[1] + o[2] * a[2];
  const double rd = r[0] * a[0] + r[1] * a[1] + r[2] * a[2];
  const double op[3] = {o[0] - od * a[0], o[1] - od * a[1], o[2] - od * a[2]};
  const double rp[3] = {r[0] - rd * a[0], r[1] - rd * a[1], r[2] - rd * a[2]};
  const double A = rp[0] * rp[0] + rp[1] * rp[1] + rp[2] * rp[2];
  const double B = 2.0 * (op[0] * rp[0] + op[1] * rp[1] + op[2] * rp[2]);
  const double C = op[0] * op[0] + op[1] * op[1] + op[2] * op[2] - c.radius * c.radius;
  const double disc = B * B - 4.0 * A * C;
  if (A < 1e-12 || disc < 0.0) return false;
  const double t = (-B - std::sqrt(disc)) / (2.0 * A);
  const double axial = od + t * rd;
  if (t <= 0.0 || axial < c.t0 || axial > c.t1) return false;
  *t_out = t;
  return true;
}

// Renders the scene into `points` (resized) and returns a view of it.
inline estimator::OrganizedCloud render(const SyntheticScene& s,
                                        std::vector<estimator::CloudPoint>* points,
                                        std::uint64_t frame_id = 0) {
  points->assign(static_cast<std::size_t>(s.width * s.height), estimator::CloudPoint{});
  std::uint64_t state = s.seed * 0x9e3779b97f4a7c15ull + frame_id;
  auto uniform = [&state]() {
    state = state * 6364136223846793005ull + 1442695040888963407ull;
    return static_cast<double>(state >> 11) * 0x1.0p-53;
  };
  for (int v = 0; v < s.height; ++v) {
    for (int u = 0; u < s.width; ++u) {
      double r[3] = {(u - s.cx) / s.f_px, (v - s.cy) / s.f_px, 1.0};
      const double len = std::sqrt(r[0] * r[0] + r[1] * r[1] + 1.0);
      for (double& x : r) x /= len;
      double t = 1e9;
      const double denom = s.nx * r[0] + s.ny * r[1] + s.nz * r[2];
      if (denom < -1e-9) t = s.d / -denom;
      for (const Cylinder& c : s.cylinders) {
        double tc;
        if (hit_cylinder(c, r, &tc) && tc < t) t = tc;
      }
      if (t > 100.0) continue;
      if (s.noise_m > 0.0) {
        // Sum of uniforms: roughly normal, deterministic, enough for tests.
        double n = 0.0;
        for (int k = 0; k < 12; ++k) n += uniform();
        t += s.noise_m * (n - 6.0);
      }
      (*points)[static_cast<std::size_t>(v * s.width + u)] = {static_cast<float>(t * r[0]),
                                                              static_cast<float>(t * r[1]),
                                                              static_cast<float>(t * r[2]),
                                                              static_cast<float>(s.noise_m),
                                                              1000,
                                                              255};
    }
  }
  estimator::OrganizedCloud cloud;
  cloud.frame_id = frame_id;
  cloud.capture_time_us = static_cast<std::int64_t>(frame_id) * 1000;
  cloud.width = static_cast<std::uint32_t>(s.width);
  cloud.height = static_cast<std::uint32_t>(s.height);
  cloud.points = points->data();
  return cloud;
}

}  // namespace testing_support
