#include "tof/raw_frame.hpp"

namespace tof {

const char* to_string(Mode mode) {
  switch (mode) {
    case Mode::kMode9:
      return "MODE_9";
    case Mode::kMode5:
      return "MODE_5";
  }
  return "UNKNOWN";
}

// Zeroed, for the largest mode, once.
RawFrame::RawFrame() : samples_(new std::uint16_t[kMaxRawImages * kPixels]()) {}

}  // namespace tof
