// The per-pixel pass, four pixels at a time: each frequency's phase,
// amplitude and noise from its four phase steps with the calibration
// removed, then (MODE_9) the two frequencies unwrapped into one distance.
#include <cmath>

#include "tof/processor.hpp"
#include "vector4.hpp"

namespace tof {
namespace {

using v4::Floats4;
using v4::Ints4;

// The pass writes states as lane values; these are PixelState's.
static_assert(static_cast<int>(PixelState::kValid) == 0 &&
                  static_cast<int>(PixelState::kSaturated) == 1 &&
                  static_cast<int>(PixelState::kDark) == 2 &&
                  static_cast<int>(PixelState::kInconsistent) == 3 &&
                  static_cast<int>(PixelState::kOutOfRange) == 4 &&
                  static_cast<int>(PixelState::kNoisy) == 5,
              "phase_pass's lane values");

// One frequency's result for four pixels.
struct FrequencyResult {
  Floats4 distance_m;  // wrapped, in [0, unambiguous)
  Floats4 sigma_m;     // standard deviation of distance_m
  Floats4 amplitude_dn;
  Ints4 saturated;
};

struct Wiggle {
  const float* cos_rad;
  const float* sin_rad;
};

// The wiggle w(phase) and its slope, from cos and sin of the phase by the
// harmonics' recurrence (no trigonometric calls).
void wiggle_and_slope(const Wiggle& w, Floats4 c1, Floats4 s1, Floats4* value, Floats4* slope) {
  Floats4 ch = c1, sh = s1;
  Floats4 sum = w.cos_rad[0] * ch + w.sin_rad[0] * sh;
  Floats4 d = w.sin_rad[0] * ch - w.cos_rad[0] * sh;
  for (int h = 1; h < kWiggleHarmonics; ++h) {
    const Floats4 cn = ch * c1 - sh * s1, sn = sh * c1 + ch * s1;
    ch = cn;
    sh = sn;
    sum += w.cos_rad[h] * ch + w.sin_rad[h] * sh;
    d += static_cast<float>(h + 1) * (w.sin_rad[h] * ch - w.cos_rad[h] * sh);
  }
  *value = sum;
  *slope = d;
}

}  // namespace

void Processor::phase_pass(const RawFrame& raw, float temperature_offset_m) {
  static_assert(kPixels % 4 == 0, "the pass works on whole blocks of four pixels");
  const int frequencies = frequency_count(raw.mode);
  const ProcessingConfig& c = config_;
  const Floats4 zero = v4::splat(0.0f);
  const float saturation = static_cast<float>(c.saturation_dn);
  for (int s = 0; s < kPixelStates; ++s) counts_.by_state[s] = 0;

  for (std::size_t i = 0; i < kPixels; i += 4) {
    FrequencyResult r[kMaxFrequencies];
    for (int f = 0; f < frequencies; ++f) {
      const FrequencyConstants& k = freq_[f];
      const Floats4 s0 = v4::load_samples(raw.phase_image(f, 0) + i);
      const Floats4 s1 = v4::load_samples(raw.phase_image(f, 1) + i);
      const Floats4 s2 = v4::load_samples(raw.phase_image(f, 2) + i);
      const Floats4 s3 = v4::load_samples(raw.phase_image(f, 3) + i);
      r[f].saturated =
          (s0 >= saturation) | (s1 >= saturation) | (s2 >= saturation) | (s3 >= saturation);
      // Opposite steps cancel the background: I = 2 A cos(phase),
      // Q = 2 A sin(phase).
      const Floats4 in_phase = s0 - s2, quadrature = s3 - s1;
      const Floats4 norm2 = in_phase * in_phase + quadrature * quadrature;
      const Floats4 norm = v4::sqrt4(norm2);
      const Floats4 inv_norm = 1.0f / v4::max4(norm, v4::splat(1e-6f));
      Floats4 wiggle, slope;
      wiggle_and_slope({k.wiggle_cos_rad, k.wiggle_sin_rad}, in_phase * inv_norm,
                       quadrature * inv_norm, &wiggle, &slope);
      // measured = true + w(true): one fixed-point step from the measured
      // phase and its first-order correction (error ~ w * w'^2).
      const Floats4 phase =
          v4::atan2_4(quadrature, in_phase) - wiggle + slope * wiggle - k.phase_offset_rad;
      Floats4 d =
          phase * k.range_per_rad_m - v4::load(pixel_offset_m_.get() + i) - temperature_offset_m;
      d -= k.unambiguous_m * v4::floor4(d * (1.0f / k.unambiguous_m));
      r[f].distance_m = d;
      r[f].amplitude_dn = 0.5f * norm;
      // Shot noise of everything the pixel collected (signal and ambient,
      // the phase steps' mean above black) and read noise, per sample;
      // the phase's noise is that over sqrt(2) A.
      const Floats4 collected = (s0 + s1 + s2 + s3) * 0.25f - black_level_dn_;
      const Floats4 variance = v4::max4(collected, zero) * inverse_gain_ + read_variance_dn2_;
      r[f].sigma_m = v4::sqrt4(variance) * k.range_per_rad_m /
                     (1.41421356f * v4::max4(r[f].amplitude_dn, v4::splat(1e-3f)));
    }

    Floats4 range = r[0].distance_m, sigma = r[0].sigma_m, amplitude = r[0].amplitude_dn;
    Ints4 saturated = r[0].saturated;
    Ints4 dark = r[0].amplitude_dn < c.min_amplitude_dn;
    Ints4 inconsistent = {0, 0, 0, 0};
    if (frequencies == 2) {
      // Try each wrap n of the first frequency; the second's nearest wrap
      // to it gives a residual. The best residual must be within the
      // noise; the wrong wraps are at least twice the largest tolerance
      // away (checked at init), so a pixel within it is not a guess.
      const FrequencyConstants &k0 = freq_[0], &k1 = freq_[1];
      const Floats4 d0 = r[0].distance_m, d1 = r[1].distance_m;
      Floats4 best = v4::splat(1e30f), best0 = zero, best1 = zero;
      for (int n = 0; n < unwrap_candidates_; ++n) {
        const Floats4 cand0 = d0 + static_cast<float>(n) * k0.unambiguous_m;
        const Floats4 m = v4::floor4((cand0 - d1) * (1.0f / k1.unambiguous_m) + 0.5f);
        const Floats4 cand1 = d1 + m * k1.unambiguous_m;
        const Floats4 residual = v4::abs4(cand0 - cand1);
        const Ints4 better = residual < best;
        best = better ? residual : best;
        best0 = better ? cand0 : best0;
        best1 = better ? cand1 : best1;
      }
      // Inverse-variance weights: the finer frequency counts for more.
      const Floats4 w0 = 1.0f / (r[0].sigma_m * r[0].sigma_m + 1e-12f);
      const Floats4 w1 = 1.0f / (r[1].sigma_m * r[1].sigma_m + 1e-12f);
      range = (w0 * best0 + w1 * best1) / (w0 + w1);
      sigma = v4::sqrt4(1.0f / (w0 + w1));
      const Floats4 diff_sigma =
          v4::sqrt4(r[0].sigma_m * r[0].sigma_m + r[1].sigma_m * r[1].sigma_m);
      const Floats4 tolerance =
          v4::min4(v4::max4(c.unwrap_sigmas * diff_sigma, v4::splat(c.unwrap_min_tolerance_m)),
                   v4::splat(c.unwrap_max_tolerance_m));
      inconsistent = best > tolerance;
      amplitude = 0.5f * (r[0].amplitude_dn + r[1].amplitude_dn);
      saturated |= r[1].saturated;
      dark |= r[1].amplitude_dn < c.min_amplitude_dn;
    }
    const Ints4 out_of_range = (range < c.min_range_m) | (range > unwrap_limit_m_);
    const Ints4 noisy = sigma > c.noise_cutoff_m;
    // The first reason wins: saturation and darkness make the phase
    // meaningless, so they come before the tests on distance.
    Ints4 state = noisy ? Ints4{5, 5, 5, 5} : Ints4{0, 0, 0, 0};
    state = out_of_range ? Ints4{4, 4, 4, 4} : state;
    state = inconsistent ? Ints4{3, 3, 3, 3} : state;
    state = dark ? Ints4{2, 2, 2, 2} : state;
    state = saturated ? Ints4{1, 1, 1, 1} : state;
    range = state == 0 ? range : zero;
    v4::store(range_m_.get() + i, range);
    v4::store(noise_m_.get() + i, sigma);
    v4::store(amplitude_dn_.get() + i, amplitude);
    for (int k = 0; k < 4; ++k) state_[i + k] = static_cast<PixelState>(state[k]);
  }
}

}  // namespace tof
