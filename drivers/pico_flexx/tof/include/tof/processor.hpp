#pragma once
// The robot's time-of-flight processing: raw phase images (raw_frame.hpp)
// and the unit's calibration (calibration.hpp) in, the project's depth
// frame (hal/depth_frame.hpp: x, y, z, noise, grey, confidence) out.
//
// Per pixel, four at a time: phase and amplitude of each frequency from its
// four phase steps; the calibration removed (wiggling, the frequency's
// phase offset, the pixel's fixed-pattern offset, temperature drift); the
// two frequencies unwrapped into one distance, or the pixel marked
// inconsistent when no pair of wraps agrees within the noise; noise from
// amplitude and the imager's shot and read noise; then the flying-pixel
// test on the distances and the points along the undistorted pixel rays.
//
// Everything is sized at construction: process() allocates nothing,
// throws nothing and runs a fixed number of steps per pixel.
#include <cstdint>
#include <memory>

#include "hal/depth_frame.hpp"
#include "tof/calibration.hpp"
#include "tof/raw_frame.hpp"

namespace tof {

struct ProcessingConfig {
  // A pixel with any phase sample at or above this is saturated (the
  // 12-bit ADC's top code).
  std::uint16_t saturation_dn = kMaxSampleDn;
  // A pixel whose amplitude (of either frequency) is below this is too dark.
  float min_amplitude_dn = 6.0f;
  // Pixels noisier than this are dropped (the vendor's default).
  float noise_cutoff_m = 0.07f;
  float min_range_m = 0.1f;
  float max_range_m = 6.0f;
  // MODE_9 unwrapping: the two frequencies' distances must agree within
  // unwrap_sigmas times the noise of their difference, kept inside
  // [unwrap_min_tolerance_m, unwrap_max_tolerance_m]. The maximum must stay
  // below half the distance between the frequencies' wrong candidates
  // (init_status() checks it).
  float unwrap_sigmas = 4.0f;
  float unwrap_min_tolerance_m = 0.02f;
  float unwrap_max_tolerance_m = 0.2f;
  // The vendor's flying-pixel test (a jump to both horizontal or both
  // vertical neighbours).
  bool flying_filter = true;
  // With it, a second look at what that test left: a pixel no valid
  // neighbour agrees with, beside mixed returns or a jump, is dropped as
  // flying too (an edge's mixed pixels two or three together).
  bool strand_filter = true;
  // A frame whose imager temperature lies further than this from the
  // calibration's reference is refused: the drift correction (about
  // 0.9 mm/K) is a straight line measured near the reference, and a
  // header saying 300 deg C would move a wall at 1 m by a quarter metre
  // with every pixel valid. 45 K around a 25 deg C reference is -20 to
  // 70 deg C, the imager's die in any cabin the camera works in.
  float max_temperature_offset_k = 45.0f;
};

enum class ProcessStatus : std::uint8_t {
  kOk,
  kBadCalibration,          // init: check_calibration failed
  kBadConfig,               // init: a limit out of order, or the tolerance too wide to unwrap
  kModeNotCalibrated,       // a MODE_9 frame with a one-frequency calibration
  kNotInitialized,          // process() on a processor whose init failed
  kImplausibleTemperature,  // the frame's imager temperature is not finite or lies further
                            // than max_temperature_offset_k from the reference
};
const char* to_string(ProcessStatus status);

// Why a pixel is invalid (or that it is not), the first reason found.
enum class PixelState : std::uint8_t {
  kValid,
  kSaturated,
  kDark,
  kInconsistent,  // the frequencies disagree: mixed returns, multipath, or noise
  kOutOfRange,
  kNoisy,
  kFlying,
};
const char* to_string(PixelState state);
constexpr int kPixelStates = 7;

struct PixelCounts {
  std::uint32_t by_state[kPixelStates] = {};
  std::uint32_t of(PixelState s) const { return by_state[static_cast<int>(s)]; }
};

class Processor {
 public:
  Processor(const Calibration& calibration, const ProcessingConfig& config);

  ProcessStatus init_status() const { return init_status_; }

  // Turns `raw` into a depth frame. `out` views the processor's points,
  // valid until the next call.
  [[nodiscard]] ProcessStatus process(const RawFrame& raw, hal::DepthFrame* out);

  const PixelCounts& last_counts() const { return counts_; }
  // The last frame's radial distances (0 = invalid) and pixel states.
  const float* range_m() const { return range_m_.get(); }
  const PixelState* pixel_state() const { return state_.get(); }
  // Unit ray of each pixel (camera frame, x right, y down, z forward).
  void ray(std::size_t pixel, float* x, float* y, float* z) const;
  // How far MODE_9 distances go before they alias: c / (2 gcd(f1, f2)),
  // bounded by max_range_m.
  float unwrap_limit_m() const { return unwrap_limit_m_; }

 private:
  struct FrequencyConstants {
    float unambiguous_m;    // c / (2 f)
    float range_per_rad_m;  // c / (4 pi f)
    float phase_offset_rad;
    float wiggle_cos_rad[kWiggleHarmonics];
    float wiggle_sin_rad[kWiggleHarmonics];
  };
  ProcessStatus init(const Calibration& calibration);
  void compute_rays(const Calibration& calibration);
  void phase_pass(const RawFrame& raw, float temperature_offset_m);
  void flying_pixel_pass();
  void strand_pass();
  void write_points();

  ProcessingConfig config_;
  ProcessStatus init_status_ = ProcessStatus::kNotInitialized;
  int frequency_count_ = 0;
  FrequencyConstants freq_[kMaxFrequencies] = {};
  int unwrap_candidates_ = 1;  // wraps of the first frequency tried
  float unwrap_limit_m_ = 0.0f;
  float black_level_dn_ = 0.0f, inverse_gain_ = 0.0f, read_variance_dn2_ = 0.0f;
  double reference_temperature_c_ = 25.0, temperature_drift_m_per_k_ = 0.0;
  // Per-pixel tables, kPixels each, built at construction.
  std::unique_ptr<float[]> ray_x_, ray_y_, ray_z_, pixel_offset_m_;
  // Per-frame work, kPixels each.
  std::unique_ptr<float[]> range_m_, noise_m_, amplitude_dn_;
  std::unique_ptr<PixelState[]> state_;
  std::unique_ptr<hal::DepthPoint[]> points_;
  PixelCounts counts_;
};

}  // namespace tof
