#pragma once
// The Pico Flexx's operating modes ("use cases"). The name encodes the raw
// frames per depth frame, the frame rate and the longest exposure.
#include <cstdint>
#include <string_view>

namespace hal {

struct UseCase {
  const char* name;         // e.g. "MODE_5_45FPS_500"
  std::uint8_t raw_frames;  // 9 = two modulation frequencies, 5 = one
  std::uint16_t frame_rate_hz;
  std::uint16_t max_exposure_us;
};

// The camera's supported use cases, in the vendor's order.
const UseCase* use_cases(std::size_t* count);

// nullptr when the name is not a supported use case.
const UseCase* find_use_case(std::string_view name);

// The time between frames, which is also the estimator's budget per frame.
inline std::int64_t frame_period_us(const UseCase& use_case) {
  return 1000000 / static_cast<std::int64_t>(use_case.frame_rate_hz);
}

}  // namespace hal
