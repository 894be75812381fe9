// The processor's set-up (tables sized and filled once) and the frame's
// three passes in order; the passes are phase_pass.cpp and
// flying_pixels.cpp.
#include "tof/processor.hpp"

#include <cmath>

namespace tof {

const char* to_string(ProcessStatus status) {
  switch (status) {
    case ProcessStatus::kOk:
      return "OK";
    case ProcessStatus::kBadCalibration:
      return "BAD_CALIBRATION";
    case ProcessStatus::kBadConfig:
      return "BAD_CONFIG";
    case ProcessStatus::kModeNotCalibrated:
      return "MODE_NOT_CALIBRATED";
    case ProcessStatus::kNotInitialized:
      return "NOT_INITIALIZED";
    case ProcessStatus::kImplausibleTemperature:
      return "IMPLAUSIBLE_TEMPERATURE";
  }
  return "UNKNOWN";
}

const char* to_string(PixelState state) {
  switch (state) {
    case PixelState::kValid:
      return "VALID";
    case PixelState::kSaturated:
      return "SATURATED";
    case PixelState::kDark:
      return "DARK";
    case PixelState::kInconsistent:
      return "INCONSISTENT";
    case PixelState::kOutOfRange:
      return "OUT_OF_RANGE";
    case PixelState::kNoisy:
      return "NOISY";
    case PixelState::kFlying:
      return "FLYING";
  }
  return "UNKNOWN";
}

Processor::Processor(const Calibration& calibration, const ProcessingConfig& config)
    : config_(config),
      ray_x_(new float[kPixels]()),
      ray_y_(new float[kPixels]()),
      ray_z_(new float[kPixels]()),
      pixel_offset_m_(new float[kPixels]()),
      range_m_(new float[kPixels]()),
      noise_m_(new float[kPixels]()),
      amplitude_dn_(new float[kPixels]()),
      state_(new PixelState[kPixels]()),
      points_(new hal::DepthPoint[kPixels]()) {
  init_status_ = init(calibration);
}

namespace {

// How far apart, at best, the first frequency's k-th wrong wrap lands from
// any wrap of the second: the margin by which unwrapping tells them apart.
double wrong_wrap_separation_m(double u1_m, double u2_m, int k) {
  const double d = k * u1_m;
  const double r = d - u2_m * std::floor(d / u2_m);
  return std::fmin(r, u2_m - r);
}

}  // namespace

ProcessStatus Processor::init(const Calibration& cal) {
  if (check_calibration(cal) != CalibrationStatus::kOk) return ProcessStatus::kBadCalibration;
  const ProcessingConfig& c = config_;
  if (!(c.min_range_m > 0.0f && c.min_range_m < c.max_range_m && c.max_range_m <= 20.0f) ||
      !(c.noise_cutoff_m > 0.0f) || !(c.min_amplitude_dn >= 0.0f) || !(c.unwrap_sigmas > 0.0f) ||
      !(c.unwrap_min_tolerance_m > 0.0f && c.unwrap_min_tolerance_m <= c.unwrap_max_tolerance_m) ||
      !(c.max_temperature_offset_k > 0.0f && c.max_temperature_offset_k <= 200.0f)) {
    return ProcessStatus::kBadConfig;
  }
  frequency_count_ = cal.frequency_count;
  for (int f = 0; f < frequency_count_; ++f) {
    const FrequencyCalibration& fc = cal.frequency[f];
    FrequencyConstants& k = freq_[f];
    k.unambiguous_m = static_cast<float>(unambiguous_range_m(fc.frequency_hz));
    k.range_per_rad_m = static_cast<float>(unambiguous_range_m(fc.frequency_hz) / (2.0 * M_PI));
    k.phase_offset_rad = static_cast<float>(fc.phase_offset_rad);
    for (int h = 0; h < kWiggleHarmonics; ++h) {
      k.wiggle_cos_rad[h] = static_cast<float>(fc.wiggle_cos_rad[h]);
      k.wiggle_sin_rad[h] = static_cast<float>(fc.wiggle_sin_rad[h]);
    }
  }
  // The first frequency's wraps tried: as many as reach max_range_m, and
  // no more than stay apart from the second's by twice the tolerance.
  unwrap_candidates_ = 1;
  unwrap_limit_m_ = freq_[0].unambiguous_m;
  if (frequency_count_ == 2) {
    const double u1 = freq_[0].unambiguous_m, u2 = freq_[1].unambiguous_m;
    const int wanted = static_cast<int>(std::ceil(c.max_range_m / u1));
    for (int n = 2; n <= wanted && n <= 16; ++n) {
      if (wrong_wrap_separation_m(u1, u2, n - 1) <= 2.0 * c.unwrap_max_tolerance_m) break;
      // Every earlier k was checked on the way here.
      unwrap_candidates_ = n;
    }
    unwrap_limit_m_ = static_cast<float>(std::fmin(c.max_range_m, unwrap_candidates_ * u1));
    if (wrong_wrap_separation_m(u1, u2, 1) <= 2.0 * c.unwrap_max_tolerance_m) {
      return ProcessStatus::kBadConfig;
    }
  }
  black_level_dn_ = static_cast<float>(cal.black_level_dn);
  inverse_gain_ = static_cast<float>(1.0 / cal.conversion_gain_e_per_dn);
  read_variance_dn2_ = static_cast<float>(cal.read_noise_dn * cal.read_noise_dn);
  reference_temperature_c_ = cal.reference_temperature_c;
  temperature_drift_m_per_k_ = cal.temperature_drift_m_per_k;
  for (std::uint32_t row = 0; row < kHeightPx; ++row) {
    for (std::uint32_t col = 0; col < kWidthPx; ++col) {
      pixel_offset_m_[row * kWidthPx + col] = static_cast<float>(pixel_offset_m(cal, row, col));
    }
  }
  compute_rays(cal);
  return ProcessStatus::kOk;
}

// The unit ray of every pixel: the pixel's normalised, distorted image
// point undistorted by fixed-point iteration (a few steps for this mild
// lens; 30 at most) and normalised, once.
void Processor::compute_rays(const Calibration& cal) {
  const hal::LensParameters& l = cal.lens;
  for (std::uint32_t row = 0; row < kHeightPx; ++row) {
    for (std::uint32_t col = 0; col < kWidthPx; ++col) {
      const double xd = (col - l.cx_px) / l.fx_px, yd = (row - l.cy_px) / l.fy_px;
      double x = xd, y = yd;
      for (int it = 0; it < 30; ++it) {
        const double r2 = x * x + y * y;
        const double radial = 1.0 + r2 * (l.k1 + r2 * (l.k2 + r2 * l.k3));
        const double ex = x * radial + 2.0 * l.p1 * x * y + l.p2 * (r2 + 2.0 * x * x) - xd;
        const double ey = y * radial + l.p1 * (r2 + 2.0 * y * y) + 2.0 * l.p2 * x * y - yd;
        x -= ex;
        y -= ey;
        if (ex * ex + ey * ey < 1e-24) break;
      }
      const double norm = std::sqrt(x * x + y * y + 1.0);
      const std::size_t i = static_cast<std::size_t>(row) * kWidthPx + col;
      ray_x_[i] = static_cast<float>(x / norm);
      ray_y_[i] = static_cast<float>(y / norm);
      ray_z_[i] = static_cast<float>(1.0 / norm);
    }
  }
}

void Processor::ray(std::size_t pixel, float* x, float* y, float* z) const {
  *x = ray_x_[pixel];
  *y = ray_y_[pixel];
  *z = ray_z_[pixel];
}

ProcessStatus Processor::process(const RawFrame& raw, hal::DepthFrame* out) {
  if (init_status_ != ProcessStatus::kOk) return ProcessStatus::kNotInitialized;
  if (frequency_count(raw.mode) > frequency_count_) return ProcessStatus::kModeNotCalibrated;
  if (!(std::fabs(raw.sensor_temperature_c - reference_temperature_c_) <=
        config_.max_temperature_offset_k)) {
    return ProcessStatus::kImplausibleTemperature;
  }
  const float temperature_offset_m = static_cast<float>(
      temperature_drift_m_per_k_ * (raw.sensor_temperature_c - reference_temperature_c_));
  phase_pass(raw, temperature_offset_m);
  if (config_.flying_filter) flying_pixel_pass();
  write_points();
  out->frame_id = raw.frame_id;
  out->capture_time_us = raw.capture_time_us;
  out->width = kWidthPx;
  out->height = kHeightPx;
  out->points = points_.get();
  return ProcessStatus::kOk;
}

}  // namespace tof
