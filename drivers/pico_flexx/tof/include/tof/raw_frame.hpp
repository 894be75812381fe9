#pragma once
// Raw continuous-wave time-of-flight frames as the Pico Flexx's imager
// delivers them: per modulation frequency four 12-bit correlation images
// taken at phase steps of 0, 90, 180 and 270 deg, then one grey-scale image
// taken with the illumination off (ambient light only). MODE_9 use cases
// carry two frequencies (8 + 1 images), MODE_5 one (4 + 1).
//
// Layout: planar, one image after the other, each row major (the order the
// imager reads them out). The buffer is sized once, for the largest mode.
#include <cstddef>
#include <cstdint>
#include <memory>

namespace tof {

constexpr std::uint32_t kWidthPx = 224;
constexpr std::uint32_t kHeightPx = 171;
constexpr std::size_t kPixels = static_cast<std::size_t>(kWidthPx) * kHeightPx;
constexpr int kMaxFrequencies = 2;
constexpr int kPhaseSteps = 4;
constexpr int kMaxRawImages = kMaxFrequencies * kPhaseSteps + 1;
// 12-bit samples: the ADC's largest code, which is also what a saturated
// pixel reads.
constexpr std::uint16_t kMaxSampleDn = 4095;
// Speed of light in vacuum (the cabin's air changes it by 3e-4, 1 mm at
// 4 m, inside the calibration's global offset).
constexpr double kSpeedOfLight_m_s = 299792458.0;

enum class Mode : std::uint8_t {
  kMode9,  // two frequencies x four phase steps + grey
  kMode5,  // one frequency x four phase steps + grey
};
const char* to_string(Mode mode);
inline int frequency_count(Mode mode) {
  return mode == Mode::kMode9 ? 2 : 1;
}
inline int raw_image_count(Mode mode) {
  return frequency_count(mode) * kPhaseSteps + 1;
}

// One raw frame. Owns its samples (allocated at construction, never again).
class RawFrame {
 public:
  RawFrame();

  Mode mode = Mode::kMode9;
  std::uint64_t frame_id = 0;
  std::int64_t capture_time_us = 0;
  std::uint32_t exposure_us = 0;       // per phase image
  float sensor_temperature_c = 25.0f;  // the imager's own sensor, per frame

  // Image `image` (0..8): frequency f's phase step k is image f * 4 + k;
  // the grey image is the last (4 for MODE_5, 8 for MODE_9).
  std::uint16_t* image(int image) {
    return samples_.get() + static_cast<std::size_t>(image) * kPixels;
  }
  const std::uint16_t* image(int image) const {
    return samples_.get() + static_cast<std::size_t>(image) * kPixels;
  }
  std::uint16_t* phase_image(int frequency, int step) {
    return image(frequency * kPhaseSteps + step);
  }
  const std::uint16_t* phase_image(int frequency, int step) const {
    return image(frequency * kPhaseSteps + step);
  }
  std::uint16_t* grey_image() { return image(raw_image_count(mode) - 1); }
  const std::uint16_t* grey_image() const { return image(raw_image_count(mode) - 1); }

 private:
  std::unique_ptr<std::uint16_t[]> samples_;
};

}  // namespace tof
