#pragma once
// First and second moments of a 3-D point set, for least-squares planes
// and principal axes. Sums are taken in double about a reference point near
// the set so that the covariance stays well conditioned; plain scalar sums,
// inline, since they run over thousands of points per frame.
#include <Eigen/Core>

namespace estimator {

struct PointMoments {
  double rx = 0.0, ry = 0.0, rz = 0.0;  // the reference point
  double n = 0.0;
  double sx = 0.0, sy = 0.0, sz = 0.0;
  double sxx = 0.0, sxy = 0.0, sxz = 0.0, syy = 0.0, syz = 0.0, szz = 0.0;

  void set_reference(double x, double y, double z) {
    rx = x;
    ry = y;
    rz = z;
  }
  void add(double x, double y, double z) {
    const double qx = x - rx, qy = y - ry, qz = z - rz;
    n += 1.0;
    sx += qx;
    sy += qy;
    sz += qz;
    sxx += qx * qx;
    sxy += qx * qy;
    sxz += qx * qz;
    syy += qy * qy;
    syz += qy * qz;
    szz += qz * qz;
  }
  // Valid for n > 0.
  Eigen::Vector3d mean() const { return {rx + sx / n, ry + sy / n, rz + sz / n}; }
  Eigen::Matrix3d covariance() const {
    const Eigen::Vector3d m(sx / n, sy / n, sz / n);
    Eigen::Matrix3d second;
    second << sxx, sxy, sxz, sxy, syy, syz, sxz, syz, szz;
    return second / n - m * m.transpose();
  }
};

}  // namespace estimator
