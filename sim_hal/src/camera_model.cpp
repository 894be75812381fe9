#include "sim_hal/camera_model.hpp"

namespace sim_hal {

CameraIntrinsics pico_flexx_intrinsics() {
  CameraIntrinsics cam;
  // Square pixels at 206 px focal length give the 45 deg vertical field;
  // barrel distortion (k1) stretches the horizontal field to 62 deg.
  cam.lens.fx_px = 206.0;
  cam.lens.fy_px = 206.0;
  cam.lens.cx_px = 111.3;
  cam.lens.cy_px = 86.1;
  cam.lens.k1 = -0.25;
  cam.lens.k2 = 0.02;
  cam.lens.k3 = 0.0;
  cam.lens.p1 = 0.0008;
  cam.lens.p2 = -0.0005;
  return cam;
}

Eigen::Vector2d distort(const hal::LensParameters& l, const Eigen::Vector2d& p) {
  const double x = p.x(), y = p.y();
  const double r2 = x * x + y * y;
  const double radial = 1.0 + r2 * (l.k1 + r2 * (l.k2 + r2 * l.k3));
  return {x * radial + 2.0 * l.p1 * x * y + l.p2 * (r2 + 2.0 * x * x),
          y * radial + l.p1 * (r2 + 2.0 * y * y) + 2.0 * l.p2 * x * y};
}

Eigen::Vector2d undistort(const hal::LensParameters& l, const Eigen::Vector2d& d) {
  Eigen::Vector2d u = d;
  for (int it = 0; it < 30; ++it) {
    const Eigen::Vector2d err = distort(l, u) - d;
    u -= err;
    if (err.squaredNorm() < 1e-24) break;
  }
  return u;
}

bool within_lens_model(const hal::LensParameters& l, const Eigen::Vector2d& p) {
  // d(r * radial(r^2)) / dr: positive while the model still maps larger
  // angles farther out. Past its first zero the polynomial folds back, and a
  // point far outside the field (65 deg off axis with this lens's k1) would
  // land inside the image.
  const double r2 = p.squaredNorm();
  return 1.0 + r2 * (3.0 * l.k1 + r2 * (5.0 * l.k2 + r2 * 7.0 * l.k3)) > 0.0;
}

bool project(const CameraIntrinsics& cam, const Eigen::Vector3d& p, Eigen::Vector2d* pixel) {
  if (p.z() <= 1e-9) return false;
  const Eigen::Vector2d undistorted(p.x() / p.z(), p.y() / p.z());
  if (!within_lens_model(cam.lens, undistorted)) return false;
  const Eigen::Vector2d d = distort(cam.lens, undistorted);
  *pixel = {cam.lens.cx_px + cam.lens.fx_px * d.x(), cam.lens.cy_px + cam.lens.fy_px * d.y()};
  return true;
}

std::vector<Eigen::Vector3f> pixel_rays(const CameraIntrinsics& cam) {
  std::vector<Eigen::Vector3f> rays(static_cast<std::size_t>(cam.width) * cam.height);
  for (std::uint32_t row = 0; row < cam.height; ++row) {
    for (std::uint32_t col = 0; col < cam.width; ++col) {
      const Eigen::Vector2d d((col - cam.lens.cx_px) / cam.lens.fx_px,
                              (row - cam.lens.cy_px) / cam.lens.fy_px);
      const Eigen::Vector2d u = undistort(cam.lens, d);
      rays[row * cam.width + col] = Eigen::Vector3d(u.x(), u.y(), 1.0).normalized().cast<float>();
    }
  }
  return rays;
}

}  // namespace sim_hal
