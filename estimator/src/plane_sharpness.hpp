#pragma once
// How sharply a view's points pile up along a normal, and the searches over
// tilts that find the faces' own normal by it (plane_estimation.cpp's step
// after RANSAC). Internal to the estimator.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstddef>
#include <cstdint>

#include "estimator/types.hpp"

namespace estimator {

// The sum of squares of a 4 mm histogram of the points' distances along `n`
// (256 bins about the first point).
std::uint64_t normal_sharpness(const Eigen::Vector3f& n, const float* x, const float* y,
                               const float* z, std::size_t m);

// A coordinate search over tilts of `n` by that measure, halving the step
// from 8 deg to 0.25 deg (6 x 4 evaluations).
Eigen::Vector3f sharpest_normal(Eigen::Vector3f n, const float* x, const float* y, const float* z,
                                std::size_t m);

// The sharpest of a grid of tilts around `plane`'s normal (2 deg apart, to
// 10 deg each way), scored on at most 128 of its inliers (within `band_m`);
// the plane's own normal when none is sharper.
Eigen::Vector3f sharpest_grid_tilt(const Plane& plane, float band_m, const float* x, const float* y,
                                   const float* z, std::size_t m);

}  // namespace estimator
