// Writing the calibration file (the reader is calibration_io.cpp).
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>

#include "tof/calibration_io.hpp"
#include "tof/raw_frame.hpp"

namespace tof {
namespace {

// The shortest of 15 or 17 significant digits that reads back exactly.
std::string num(double v) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.15g", v);
  if (std::strtod(buf, nullptr) != v) std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

std::string list(const double* v, int n) {
  std::string s = "[";
  for (int k = 0; k < n; ++k) s += (k ? ", " : "") + num(v[k]);
  return s + "]";
}

}  // namespace

std::string calibration_to_json(const Calibration& cal) {
  const hal::LensParameters& l = cal.lens;
  std::string s = "{\n  \"format_version\": " + std::to_string(cal.format_version) + ",\n";
  s += "  \"size_px\": [" + std::to_string(cal.width_px) + ", " + std::to_string(cal.height_px) +
       "],\n";
  s += "  \"lens\": {\"fx_px\": " + num(l.fx_px) + ", \"fy_px\": " + num(l.fy_px) +
       ", \"cx_px\": " + num(l.cx_px) + ", \"cy_px\": " + num(l.cy_px) +
       ",\n           \"k1\": " + num(l.k1) + ", \"k2\": " + num(l.k2) + ", \"k3\": " + num(l.k3) +
       ", \"p1\": " + num(l.p1) + ", \"p2\": " + num(l.p2) + "},\n";
  s += "  \"frequencies\": [\n";
  for (int f = 0; f < cal.frequency_count; ++f) {
    const FrequencyCalibration& fc = cal.frequency[f];
    s += "    {\"frequency_hz\": " + num(fc.frequency_hz) +
         ", \"phase_offset_rad\": " + num(fc.phase_offset_rad) +
         ",\n     \"wiggle_cos_rad\": " + list(fc.wiggle_cos_rad, kWiggleHarmonics) +
         ",\n     \"wiggle_sin_rad\": " + list(fc.wiggle_sin_rad, kWiggleHarmonics) + "}" +
         (f + 1 < cal.frequency_count ? "," : "") + "\n";
  }
  s += "  ],\n  \"pixel_offset\": {\"poly_m\": " + list(cal.pixel_offset_poly_m, kOffsetPolyTerms);
  if (!cal.pixel_offset_m.empty()) {
    // One image row per line, in micrometre steps: about 6 bytes a pixel.
    s += ",\n    \"table_mm\": [";
    for (std::size_t i = 0; i < cal.pixel_offset_m.size(); ++i) {
      char buf[24];
      std::snprintf(buf, sizeof buf, "%.3f", cal.pixel_offset_m[i] * 1e3);
      if (i % cal.width_px == 0) s += "\n      ";
      s += buf;
      if (i + 1 < cal.pixel_offset_m.size()) s += ",";
    }
    s += "]";
  }
  s += "},\n  \"temperature\": {\"reference_c\": " + num(cal.reference_temperature_c) +
       ", \"drift_m_per_k\": " + num(cal.temperature_drift_m_per_k) + "},\n";
  s += "  \"noise_model\": {\"black_level_dn\": " + num(cal.black_level_dn) +
       ", \"conversion_gain_e_per_dn\": " + num(cal.conversion_gain_e_per_dn) +
       ", \"read_noise_dn\": " + num(cal.read_noise_dn) + "}\n}\n";
  return s;
}

bool write_calibration_file(const std::string& path, const Calibration& cal, std::string* error) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  const std::string text = calibration_to_json(cal);
  out << text;
  out.close();
  if (!out) {
    *error = path + ": cannot write the calibration file";
    return false;
  }
  return true;
}

}  // namespace tof
