#pragma once
// What one Pico Flexx unit carries in its flash so that raw phase images
// become distances: the lens, the modulation frequencies, each frequency's
// phase offset and phase non-linearity ("wiggling"), the fixed-pattern
// distance offset over the sensor, the temperature drift and the imager's
// noise model. The file format is calibration_io.hpp (CALIBRATION.md).
#include <cstdint>
#include <vector>

#include "hal/depth_frame.hpp"

namespace tof {

constexpr int kCalibrationFormatVersion = 1;
// Harmonics 1..4 of the measured phase: four-step sampling of a modulation
// with odd harmonics folds them into these (the 3rd and 5th show as the 4th).
constexpr int kWiggleHarmonics = 4;
// c0 + c1 u + c2 v + c3 u^2 + c4 u v + c5 v^2 over u, v in [-1, 1] (the
// image's columns and rows, centre 0).
constexpr int kOffsetPolyTerms = 6;

struct FrequencyCalibration {
  double frequency_hz = 0.0;
  // The electronics' delay at this frequency, as a phase.
  double phase_offset_rad = 0.0;
  // Wiggling: measured phase = true phase + sum over h of
  // cos_rad[h-1] cos(h phase) + sin_rad[h-1] sin(h phase).
  double wiggle_cos_rad[kWiggleHarmonics] = {0.0, 0.0, 0.0, 0.0};
  double wiggle_sin_rad[kWiggleHarmonics] = {0.0, 0.0, 0.0, 0.0};
};

struct Calibration {
  int format_version = kCalibrationFormatVersion;
  std::uint32_t width_px = 224;
  std::uint32_t height_px = 171;
  hal::LensParameters lens;
  // MODE_9 uses both, MODE_5 the first.
  int frequency_count = 2;
  FrequencyCalibration frequency[2];
  // Path-length offset of each pixel (fixed-pattern phase noise, as a
  // distance so that one table serves every frequency): the polynomial
  // plus, when present, one value per pixel (row major).
  double pixel_offset_poly_m[kOffsetPolyTerms] = {0.0, 0.0, 0.0, 0.0, 0.0, 0.0};
  std::vector<float> pixel_offset_m;  // empty, or width * height values
  // Distance drift with the imager's temperature.
  double reference_temperature_c = 25.0;
  double temperature_drift_m_per_k = 0.0;
  // The imager's noise model: samples read black_level_dn with no light;
  // conversion_gain_e_per_dn electrons make one code (shot noise);
  // read_noise_dn is the readout's own noise.
  double black_level_dn = 200.0;
  double conversion_gain_e_per_dn = 4.0;
  double read_noise_dn = 2.0;
};

enum class CalibrationStatus : std::uint8_t {
  kOk,
  kBadVersion,
  kBadSize,  // not 224 x 171
  kBadLens,  // focal length not positive, principal point off the image, distortion not finite
  kBadFrequencies,   // count not 1 or 2, a frequency outside 1..200 MHz, two equal
  kBadWiggle,        // a coefficient not finite or so large the correction cannot converge
  kBadPixelOffsets,  // not finite, larger than 1 m, or an array of the wrong length
  kBadTemperature,
  kBadNoiseModel,
};
const char* to_string(CalibrationStatus status);

// Checks every value; the first problem found.
[[nodiscard]] CalibrationStatus check_calibration(const Calibration& cal);

// The pixel's fixed-pattern offset: polynomial plus table (if any).
double pixel_offset_m(const Calibration& cal, std::uint32_t row, std::uint32_t col);

// Unambiguous distance of one frequency, c / (2 f).
double unambiguous_range_m(double frequency_hz);

}  // namespace tof
