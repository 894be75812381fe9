#include "tof/calibration.hpp"

#include <cmath>

#include "tof/raw_frame.hpp"

namespace tof {

const char* to_string(CalibrationStatus status) {
  switch (status) {
    case CalibrationStatus::kOk:
      return "OK";
    case CalibrationStatus::kBadVersion:
      return "BAD_VERSION";
    case CalibrationStatus::kBadSize:
      return "BAD_SIZE";
    case CalibrationStatus::kBadLens:
      return "BAD_LENS";
    case CalibrationStatus::kBadFrequencies:
      return "BAD_FREQUENCIES";
    case CalibrationStatus::kBadWiggle:
      return "BAD_WIGGLE";
    case CalibrationStatus::kBadPixelOffsets:
      return "BAD_PIXEL_OFFSETS";
    case CalibrationStatus::kBadTemperature:
      return "BAD_TEMPERATURE";
    case CalibrationStatus::kBadNoiseModel:
      return "BAD_NOISE_MODEL";
  }
  return "UNKNOWN";
}

namespace {

bool finite_all(const double* v, int n) {
  for (int k = 0; k < n; ++k) {
    if (!std::isfinite(v[k])) return false;
  }
  return true;
}

bool lens_ok(const Calibration& cal) {
  const hal::LensParameters& l = cal.lens;
  const double d[5] = {l.k1, l.k2, l.k3, l.p1, l.p2};
  return l.fx_px > 0.0 && l.fy_px > 0.0 && std::isfinite(l.fx_px) && std::isfinite(l.fy_px) &&
         l.cx_px >= 0.0 && l.cx_px <= cal.width_px && l.cy_px >= 0.0 && l.cy_px <= cal.height_px &&
         finite_all(d, 5);
}

// The processing removes wiggling by one step of a fixed-point iteration
// plus its first-order term; that is exact enough (and the inverse exists)
// only while the wiggle's slope stays well below 1.
bool wiggle_ok(const FrequencyCalibration& f) {
  double slope = 0.0;
  for (int h = 0; h < kWiggleHarmonics; ++h) {
    if (!std::isfinite(f.wiggle_cos_rad[h]) || !std::isfinite(f.wiggle_sin_rad[h])) return false;
    slope += (h + 1) * (std::fabs(f.wiggle_cos_rad[h]) + std::fabs(f.wiggle_sin_rad[h]));
  }
  return slope <= 0.5;
}

}  // namespace

CalibrationStatus check_calibration(const Calibration& cal) {
  if (cal.format_version != kCalibrationFormatVersion) return CalibrationStatus::kBadVersion;
  if (cal.width_px != kWidthPx || cal.height_px != kHeightPx) return CalibrationStatus::kBadSize;
  if (!lens_ok(cal)) return CalibrationStatus::kBadLens;
  if (cal.frequency_count < 1 || cal.frequency_count > kMaxFrequencies) {
    return CalibrationStatus::kBadFrequencies;
  }
  for (int f = 0; f < cal.frequency_count; ++f) {
    const double hz = cal.frequency[f].frequency_hz;
    if (!(hz >= 1e6 && hz <= 200e6) || !std::isfinite(cal.frequency[f].phase_offset_rad)) {
      return CalibrationStatus::kBadFrequencies;
    }
    if (!wiggle_ok(cal.frequency[f])) return CalibrationStatus::kBadWiggle;
  }
  if (cal.frequency_count == 2 &&
      std::fabs(cal.frequency[0].frequency_hz - cal.frequency[1].frequency_hz) < 1e6) {
    return CalibrationStatus::kBadFrequencies;
  }
  for (double c : cal.pixel_offset_poly_m) {
    if (!std::isfinite(c) || std::fabs(c) > 1.0) return CalibrationStatus::kBadPixelOffsets;
  }
  if (!cal.pixel_offset_m.empty()) {
    if (cal.pixel_offset_m.size() != kPixels) return CalibrationStatus::kBadPixelOffsets;
    for (float v : cal.pixel_offset_m) {
      if (!std::isfinite(v) || std::fabs(v) > 1.0f) return CalibrationStatus::kBadPixelOffsets;
    }
  }
  if (!std::isfinite(cal.reference_temperature_c) ||
      std::fabs(cal.reference_temperature_c) > 150.0 ||
      !std::isfinite(cal.temperature_drift_m_per_k) ||
      std::fabs(cal.temperature_drift_m_per_k) > 0.01) {
    return CalibrationStatus::kBadTemperature;
  }
  if (!(cal.black_level_dn >= 0.0 && cal.black_level_dn < kMaxSampleDn) ||
      !(cal.conversion_gain_e_per_dn > 0.0 && cal.conversion_gain_e_per_dn < 1000.0) ||
      !(cal.read_noise_dn >= 0.0 && cal.read_noise_dn < 1000.0)) {
    return CalibrationStatus::kBadNoiseModel;
  }
  return CalibrationStatus::kOk;
}

double pixel_offset_m(const Calibration& cal, std::uint32_t row, std::uint32_t col) {
  const double u = (col + 0.5) / (0.5 * cal.width_px) - 1.0;
  const double v = (row + 0.5) / (0.5 * cal.height_px) - 1.0;
  const double* c = cal.pixel_offset_poly_m;
  double offset = c[0] + c[1] * u + c[2] * v + c[3] * u * u + c[4] * u * v + c[5] * v * v;
  if (!cal.pixel_offset_m.empty()) {
    offset += cal.pixel_offset_m[static_cast<std::size_t>(row) * cal.width_px + col];
  }
  return offset;
}

double unambiguous_range_m(double frequency_hz) {
  return kSpeedOfLight_m_s / (2.0 * frequency_hz);
}

}  // namespace tof
