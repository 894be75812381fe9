#pragma once
// Four pixels at a time with the compiler's portable 128-bit vectors (SSE2
// on the host, NEON on the BeagleBone's Cortex-A8): the same source on
// both, no intrinsics. Private to the detector's passes.
#include <cstddef>
#include <cstdint>
#include <cstring>

#include "estimator/organized_cloud.hpp"

namespace estimator {
namespace four_lanes {

typedef float Floats4 __attribute__((vector_size(16)));
typedef std::int32_t Ints4 __attribute__((vector_size(16)));

static_assert(offsetof(CloudPoint, x_m) == 0 && offsetof(CloudPoint, y_m) == 4 &&
                  offsetof(CloudPoint, z_m) == 8 && offsetof(CloudPoint, noise_m) == 12,
              "a point starts with x, y, z and noise as four floats");

// The coordinates and noise of four points, a vector each: one vector load
// per point (its first four floats) and a 4 x 4 transpose, rather than a
// scalar load and an insert per value.
inline __attribute__((always_inline)) void load_four_points(const CloudPoint* const p[4],
                                                            Floats4* x, Floats4* y, Floats4* z,
                                                            Floats4* noise) {
  Floats4 rows[4];
  for (int j = 0; j < 4; ++j) std::memcpy(&rows[j], &p[j]->x_m, sizeof rows[j]);
  const Floats4 xy01 = __builtin_shuffle(rows[0], rows[1], Ints4{0, 4, 1, 5});
  const Floats4 zn01 = __builtin_shuffle(rows[0], rows[1], Ints4{2, 6, 3, 7});
  const Floats4 xy23 = __builtin_shuffle(rows[2], rows[3], Ints4{0, 4, 1, 5});
  const Floats4 zn23 = __builtin_shuffle(rows[2], rows[3], Ints4{2, 6, 3, 7});
  *x = __builtin_shuffle(xy01, xy23, Ints4{0, 1, 4, 5});
  *y = __builtin_shuffle(xy01, xy23, Ints4{2, 3, 6, 7});
  *z = __builtin_shuffle(zn01, zn23, Ints4{0, 1, 4, 5});
  *noise = __builtin_shuffle(zn01, zn23, Ints4{2, 3, 6, 7});
}

// Four consecutive points.
inline __attribute__((always_inline)) void load_four_points(const CloudPoint* p, Floats4* x,
                                                            Floats4* y, Floats4* z,
                                                            Floats4* noise) {
  const CloudPoint* const each[4] = {p, p + 1, p + 2, p + 3};
  load_four_points(each, x, y, z, noise);
}

// Bit j set where lane j holds (all ones, as a comparison leaves it).
inline std::uint32_t lane_mask(const Ints4& lanes) {
  return (static_cast<std::uint32_t>(lanes[0]) & 1u) | (static_cast<std::uint32_t>(lanes[1]) & 2u) |
         (static_cast<std::uint32_t>(lanes[2]) & 4u) | (static_cast<std::uint32_t>(lanes[3]) & 8u);
}

}  // namespace four_lanes
}  // namespace estimator
