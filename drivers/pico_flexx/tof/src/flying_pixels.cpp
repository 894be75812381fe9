// The flying-pixel test and the frame's points. A pixel whose footprint
// straddles a depth edge mixes the two surfaces' returns and reports a
// distance between them; the vendor's test drops a pixel whose distance
// jumps to both its left and right (or both its upper and lower)
// neighbours by more than a threshold that grows with distance, because
// noise does. Decided on this frame's distances before any is dropped, so
// the test does not feed on its own output.
#include <algorithm>
#include <cmath>

#include "tof/processor.hpp"
#include "vector4.hpp"

namespace tof {
namespace {

using v4::Floats4;
using v4::Ints4;

// 0.018 m up to 1 m, rising linearly to 0.14 m at 4.5 m.
Floats4 flying_threshold_m(Floats4 range_m) {
  const Floats4 ramp = 0.018f + (range_m - 1.0f) * (0.122f / 3.5f);
  return v4::min4(v4::max4(ramp, v4::splat(0.018f)), v4::splat(0.14f));
}

}  // namespace

void Processor::flying_pixel_pass() {
  const float* r = range_m_.get();
  const Floats4 zero = v4::splat(0.0f);
  constexpr int w = static_cast<int>(kWidthPx), h = static_cast<int>(kHeightPx);
  // Blocks of four from column 1; the last block ends at column 220, so
  // columns 221 and 222 are tested one by one with the same rule.
  auto flying_one = [&](int i) {
    const float ri = r[i],
                th = std::min(0.14f, std::max(0.018f, 0.018f + (ri - 1.0f) * (0.122f / 3.5f)));
    auto jump = [&](int j) { return r[j] > 0.0f && std::fabs(ri - r[j]) > th; };
    return ri > 0.0f && ((jump(i - 1) && jump(i + 1)) || (jump(i - w) && jump(i + w)));
  };
  for (int row = 1; row < h - 1; ++row) {
    int col = 1;
    for (; col + 4 <= w - 1; col += 4) {
      const int i = row * w + col;
      const Floats4 ri = v4::load(r + i), th = flying_threshold_m(ri);
      auto jumps = [&](int offset) {
        const Floats4 rn = v4::load(r + i + offset);
        return (rn > zero) & (v4::abs4(ri - rn) > th);
      };
      const Ints4 flying = (ri > zero) & ((jumps(-1) & jumps(1)) | (jumps(-w) & jumps(w)));
      for (int k = 0; k < 4; ++k) {
        if (flying[k]) state_[i + k] = PixelState::kFlying;
      }
    }
    for (; col < w - 1; ++col) {
      if (flying_one(row * w + col)) state_[row * w + col] = PixelState::kFlying;
    }
  }
}

void Processor::write_points() {
  const float cutoff = config_.noise_cutoff_m;
  for (std::size_t i = 0; i < kPixels; ++i) {
    const PixelState s = state_[i];
    ++counts_.by_state[static_cast<int>(s)];
    hal::DepthPoint& p = points_[i];
    const float a = amplitude_dn_[i];
    p.gray_value = static_cast<std::uint16_t>(a < 4095.0f ? a : 4095.0f);
    if (s != PixelState::kValid) {
      range_m_[i] = 0.0f;
      p.x_m = p.y_m = p.z_m = p.noise_m = 0.0f;
      p.confidence = 0;
      continue;
    }
    const float d = range_m_[i], sigma = noise_m_[i];
    p.x_m = ray_x_[i] * d;
    p.y_m = ray_y_[i] * d;
    p.z_m = ray_z_[i] * d;
    p.noise_m = sigma;
    p.confidence =
        static_cast<std::uint8_t>(std::clamp(255.0f * (1.0f - sigma / cutoff), 1.0f, 255.0f));
  }
}

}  // namespace tof
