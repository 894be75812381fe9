// The simulated unit's calibration: what its flash would hold. The values
// are of the size a real Pico Flexx shows (a few mm of fixed pattern,
// wiggling of a centimetre or so, about a millimetre per kelvin) and move
// with the camera seed the way one unit differs from the next.
#include <cmath>

#include "sim_hal/sim_random.hpp"
#include "sim_hal/tof_raw_renderer.hpp"

namespace sim_hal {

tof::Calibration simulated_calibration(const CameraIntrinsics& cam, std::uint64_t camera_seed,
                                       double pixel_pattern_m) {
  SimRandom rng(mix_seed(camera_seed, 0, 77));
  auto around = [&](double centre, double spread) {
    return centre + spread * (2.0 * rng.uniform() - 1.0);
  };
  tof::Calibration cal;
  cal.width_px = cam.width;
  cal.height_px = cam.height;
  cal.lens = cam.lens;
  cal.frequency_count = 2;
  const double hz[2] = {60e6, 80e6};
  for (int f = 0; f < 2; ++f) {
    tof::FrequencyCalibration& fc = cal.frequency[f];
    fc.frequency_hz = hz[f];
    fc.phase_offset_rad = around(f == 0 ? 0.8 : -1.2, 0.3);
    // The 4th harmonic dominates (odd harmonics folded by four-step
    // sampling); the others are small.
    fc.wiggle_cos_rad[0] = around(0.0, 0.002);
    fc.wiggle_sin_rad[0] = around(0.0, 0.002);
    fc.wiggle_cos_rad[1] = around(0.003, 0.002);
    fc.wiggle_sin_rad[1] = around(-0.002, 0.002);
    fc.wiggle_cos_rad[2] = around(0.0, 0.002);
    fc.wiggle_sin_rad[2] = around(0.0, 0.002);
    fc.wiggle_cos_rad[3] = around(0.015, 0.005);
    fc.wiggle_sin_rad[3] = around(-0.01, 0.005);
  }
  const double poly[tof::kOffsetPolyTerms] = {around(0.012, 0.004), around(0.0, 0.002),
                                              around(0.0, 0.002),   around(0.004, 0.001),
                                              around(0.0, 0.001),   around(0.003, 0.001)};
  for (int k = 0; k < tof::kOffsetPolyTerms; ++k) cal.pixel_offset_poly_m[k] = poly[k];
  if (pixel_pattern_m > 0.0) {
    cal.pixel_offset_m.resize(static_cast<std::size_t>(cam.width) * cam.height);
    // Rounded to the file's micrometre steps, so the file holds the truth.
    for (float& v : cal.pixel_offset_m) {
      v = static_cast<float>(std::round(pixel_pattern_m * rng.normal() * 1e6) * 1e-6);
    }
  }
  cal.reference_temperature_c = 25.0;
  cal.temperature_drift_m_per_k = around(0.0012, 0.0003);
  cal.black_level_dn = 200.0;
  cal.conversion_gain_e_per_dn = 16.0;
  cal.read_noise_dn = 2.0;
  return cal;
}

}  // namespace sim_hal
