#pragma once
// Four pixels at a time with GCC's portable 128-bit vectors: SSE2 on the
// host, NEON on the BeagleBone's Cortex-A8, from the same source and no
// intrinsics (as the estimator's gap pass). Comparisons give all-ones
// lanes, and `mask ? a : b` selects lane by lane.
#include <cmath>
#include <cstdint>
#include <cstring>

namespace tof::v4 {

typedef float Floats4 __attribute__((vector_size(16)));
typedef std::int32_t Ints4 __attribute__((vector_size(16)));
typedef std::uint16_t U16x4 __attribute__((vector_size(8)));

inline Floats4 splat(float v) {
  return Floats4{v, v, v, v};
}

inline Floats4 load(const float* p) {
  Floats4 v;
  std::memcpy(&v, p, sizeof v);
  return v;
}
inline void store(float* p, Floats4 v) {
  std::memcpy(p, &v, sizeof v);
}

// Four 12-bit samples as floats.
inline Floats4 load_samples(const std::uint16_t* p) {
  U16x4 v;
  std::memcpy(&v, p, sizeof v);
  return __builtin_convertvector(v, Floats4);
}

// Four one-byte codes (the pixels' states) as integers.
inline Ints4 load_bytes(const void* p) {
  typedef std::uint8_t U8x4 __attribute__((vector_size(4)));
  U8x4 v;
  std::memcpy(&v, p, sizeof v);
  return __builtin_convertvector(v, Ints4);
}

inline Floats4 min4(Floats4 a, Floats4 b) {
  return a < b ? a : b;
}
inline Floats4 max4(Floats4 a, Floats4 b) {
  return a > b ? a : b;
}
inline Floats4 abs4(Floats4 v) {
  return v < 0.0f ? -v : v;
}

// Lane by lane: GCC turns this into one vector square root where the
// target has one (SSE2) and four VFP ones where it has not (NEON on
// ARMv7 has no vector square root).
inline Floats4 sqrt4(Floats4 v) {
  for (int k = 0; k < 4; ++k) v[k] = std::sqrt(v[k]);
  return v;
}

// Largest whole number not above v, for |v| < 2^31.
inline Floats4 floor4(Floats4 v) {
  const Floats4 t = __builtin_convertvector(__builtin_convertvector(v, Ints4), Floats4);
  return t > v ? t - 1.0f : t;
}

// atan2(y, x) in (-pi, pi], to 5e-7 rad (0.2 um at 60 MHz). The octant is
// folded onto atan over [0, 1], where an odd polynomial of degree 13
// (interpolating at Chebyshev nodes of x^2) holds it; (0, 0) gives 0.
inline Floats4 atan2_4(Floats4 y, Floats4 x) {
  constexpr float kHalfPi = 1.57079632679f, kPi = 3.14159265359f;
  const Floats4 ax = abs4(x), ay = abs4(y);
  const Floats4 lo = min4(ax, ay), hi = max4(ax, ay);
  const Floats4 t = lo / max4(hi, splat(1e-30f));
  const Floats4 t2 = t * t;
  Floats4 p = splat(0.00764835393f);
  p = p * t2 - 0.0363604309f;
  p = p * t2 + 0.083126453f;
  p = p * t2 - 0.13447864f;
  p = p * t2 + 0.198720403f;
  p = p * t2 - 0.33325678f;
  p = p * t2 + 0.999999226f;
  Floats4 a = p * t;
  a = ay > ax ? kHalfPi - a : a;
  a = x < 0.0f ? kPi - a : a;
  return y < 0.0f ? -a : a;
}

}  // namespace tof::v4
