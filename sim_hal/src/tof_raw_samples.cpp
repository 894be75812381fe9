// The raw renderer's last step, four pixels at a time (GCC's portable
// vectors, as the processing): the correlator's four phase-step levels
// from each pixel's summed phasor with the frequency's wiggling, then shot
// and read noise, quantisation to 12 bits and the ADC's top code.
#include <cmath>
#include <cstring>

#include "sim_hal/sim_random.hpp"
#include "sim_hal/tof_raw_renderer.hpp"

namespace sim_hal {
namespace {

typedef float Floats4 __attribute__((vector_size(16)));
typedef std::int32_t Ints4 __attribute__((vector_size(16)));
typedef std::uint16_t U16x4 __attribute__((vector_size(8)));

Floats4 load(const float* p) {
  Floats4 v;
  std::memcpy(&v, p, sizeof v);
  return v;
}
void store(float* p, Floats4 v) {
  std::memcpy(p, &v, sizeof v);
}
Floats4 max4(Floats4 a, Floats4 b) {
  return a > b ? a : b;
}
Floats4 min4(Floats4 a, Floats4 b) {
  return a < b ? a : b;
}
Floats4 sqrt4(Floats4 v) {
  for (int k = 0; k < 4; ++k) v[k] = std::sqrt(v[k]);
  return v;
}

// Samples as the ADC gives them: rounded, 0..4095 (a level above the top
// reads 4095: saturation).
void store_samples(std::uint16_t* p, Floats4 v) {
  const Floats4 top = {4095.0f, 4095.0f, 4095.0f, 4095.0f}, zero = {0.0f, 0.0f, 0.0f, 0.0f};
  const Floats4 clamped = min4(max4(v + 0.5f, zero), top);  // positive: truncation rounds
  const U16x4 q = __builtin_convertvector(__builtin_convertvector(clamped, Ints4), U16x4);
  std::memcpy(p, &q, sizeof q);
}

}  // namespace

// One standard normal per sample to come, in order, so that the noise of a
// frame depends only on its seed.
void RawRenderer::draw_normals(std::size_t count, std::uint64_t stream_seed) {
  SimRandom rng(stream_seed);
  for (std::size_t k = 0; k < count; ++k) normals_[k] = static_cast<float>(rng.normal());
}

void RawRenderer::write_samples(int frequency, tof::RawFrame* out, std::uint64_t stream_seed) {
  const tof::FrequencyCalibration& fc = calibration_.frequency[frequency];
  const std::size_t n = amplitude_.size();
  float wc[tof::kWiggleHarmonics], ws[tof::kWiggleHarmonics];
  for (int h = 0; h < tof::kWiggleHarmonics; ++h) {
    wc[h] = static_cast<float>(fc.wiggle_cos_rad[h]);
    ws[h] = static_cast<float>(fc.wiggle_sin_rad[h]);
  }
  const float black = static_cast<float>(calibration_.black_level_dn);
  for (std::size_t i = 0; i < n; i += 4) {
    const Floats4 re = load(sum_re_.data() + i), im = load(sum_im_.data() + i);
    const Floats4 a = sqrt4(re * re + im * im);
    const Floats4 inv = 1.0f / max4(a, Floats4{1e-20f, 1e-20f, 1e-20f, 1e-20f});
    const Floats4 c1 = a > 0.0f ? re * inv : Floats4{1.0f, 1.0f, 1.0f, 1.0f};
    const Floats4 s1 = im * inv;  // 0 where there is no light (im is 0 there)
    // w(phase) by the harmonics' recurrence, then the phasor turned by it
    // (w is a few hundredths of a radian: the series to w^3 is exact to
    // 1e-8).
    Floats4 ch = c1, sh = s1, wiggle = wc[0] * c1 + ws[0] * s1;
    for (int h = 1; h < tof::kWiggleHarmonics; ++h) {
      const Floats4 cn = ch * c1 - sh * s1, sn = sh * c1 + ch * s1;
      ch = cn;
      sh = sn;
      wiggle += wc[h] * ch + ws[h] * sh;
    }
    const Floats4 cw = 1.0f - 0.5f * wiggle * wiggle, sw = wiggle - wiggle * wiggle * wiggle / 6.0f;
    const Floats4 ac = a * (c1 * cw - s1 * sw), as = a * (s1 * cw + c1 * sw);
    const Floats4 base = black + load(ambient_.data() + i) + load(sum_background_.data() + i);
    // Steps 0, 90, 180, 270 deg: cos(phase + k pi / 2).
    store(step_mean_[0].data() + i, base + ac);
    store(step_mean_[1].data() + i, base - as);
    store(step_mean_[2].data() + i, base - ac);
    store(step_mean_[3].data() + i, base + as);
  }
  const bool noise = settings_.noise;
  if (noise) draw_normals(4 * n, stream_seed);
  // Shot noise: variance of the collected charge (the level above black)
  // over the conversion gain, in DN^2; plus the readout's.
  const float inv_gain = static_cast<float>(1.0 / calibration_.conversion_gain_e_per_dn);
  const float read2 = static_cast<float>(calibration_.read_noise_dn * calibration_.read_noise_dn);
  const Floats4 zero = {0.0f, 0.0f, 0.0f, 0.0f};
  for (int k = 0; k < 4; ++k) {
    std::uint16_t* step = out->phase_image(frequency, k);
    const float* mean = step_mean_[k].data();
    const float* z = normals_.data() + static_cast<std::size_t>(k) * n;
    for (std::size_t i = 0; i < n; i += 4) {
      Floats4 v = load(mean + i);
      if (noise) v += sqrt4(max4(v - black, zero) * inv_gain + read2) * load(z + i);
      store_samples(step + i, v);
    }
  }
}

// The grey image: an exposure with the illumination off, ambient only.
void RawRenderer::write_grey(tof::RawFrame* out, std::uint64_t stream_seed) {
  const std::size_t n = ambient_.size();
  const float black = static_cast<float>(calibration_.black_level_dn);
  const float inv_gain = static_cast<float>(1.0 / calibration_.conversion_gain_e_per_dn);
  const float read2 = static_cast<float>(calibration_.read_noise_dn * calibration_.read_noise_dn);
  if (settings_.noise) draw_normals(n, stream_seed);
  std::uint16_t* grey = out->grey_image();
  for (std::size_t i = 0; i < n; i += 4) {
    const Floats4 ambient = load(ambient_.data() + i);
    Floats4 v = black + ambient;
    if (settings_.noise) v += sqrt4(ambient * inv_gain + read2) * load(normals_.data() + i);
    store_samples(grey + i, v);
  }
}

}  // namespace sim_hal
