#pragma once
// Small steps the raised-run measures share (handrail_filters.cpp's side
// width test, bar_runs.cpp's bar-first candidates).
#include <cmath>

namespace estimator {
namespace run_levels {

// A pixel's noise, bounded to [0, 2 cm]; NaN counts as 0 (comparisons with
// NaN are false), so no bad value can open a window.
inline float clamp_noise(float noise_m) {
  const float positive = noise_m > 0.0f ? noise_m : 0.0f;  // a max without a branch
  return positive < 0.02f ? positive : 0.02f;
}

// The level beside a run's end along a row or column of n pixels (stride
// apart from height_m): the first valid pixel 2 to 4 pixels out (the one
// right beside it often mixes the run's return with the surface's); NaN if
// none is in the image and valid (an invalid pixel's height is -infinity).
inline float level_beside_end(const float* height_m, int stride, int n, int end, int step) {
  for (int k = 2; k <= 4; ++k) {
    const int j = end + step * k;
    if (j < 0 || j >= n) break;
    const float h = height_m[j * stride];
    if (h > -INFINITY) return h;
  }
  return NAN;
}

}  // namespace run_levels
}  // namespace estimator
