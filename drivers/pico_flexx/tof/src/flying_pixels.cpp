// The flying-pixel test and the frame's points. A pixel whose footprint
// straddles a depth edge mixes the two surfaces' returns and reports a
// distance between them; the vendor's test drops a pixel whose distance
// jumps to both its left and right (or both its upper and lower)
// neighbours by more than a threshold that grows with distance, because
// noise does. Decided on this frame's distances before any is dropped, so
// the test does not feed on its own output. Where an edge's mixed pixels
// lie two or three together (an edge seen obliquely, or running across
// the rows), one of them may have a mixed neighbour that agrees with it
// and so pass that test; a second look, on what the first left, drops a
// pixel stranded between the two surfaces (strand_pass).
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
// The same for one pixel (the columns past the last block of four).
float flying_threshold_m(float range_m) {
  return flying_threshold_m(v4::splat(range_m))[0];
}

}  // namespace

void Processor::flying_pixel_pass() {
  const float* r = range_m_.get();
  const Floats4 zero = v4::splat(0.0f);
  constexpr int w = static_cast<int>(kWidthPx), h = static_cast<int>(kHeightPx);
  // Blocks of four from column 1; the last block ends at column 220, so
  // columns 221 and 222 are tested one by one with the same rule.
  auto flying_one = [&](int i) {
    const float ri = r[i], th = flying_threshold_m(ri);
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
  if (config_.strand_filter) strand_pass();
}

// A pixel the first test left valid but that no valid neighbour (left,
// right, up, down) agrees with, beside a pixel of mixed returns (flagged
// flying, or inconsistent between the frequencies) or a jump, lies on
// neither surface of the edge. Decided on the first test's states only: a
// row's verdicts are applied once the next row has been decided, so no
// verdict of this pass feeds another. Pixels with no evidence of an edge
// around them (only dark or saturated neighbours) are left alone.
void Processor::strand_pass() {
  static_assert(sizeof(PixelState) == 1, "states are read four bytes at a time");
  const float* r = range_m_.get();
  const PixelState* st = state_.get();
  constexpr int w = static_cast<int>(kWidthPx), h = static_cast<int>(kHeightPx);
  constexpr int kValid = static_cast<int>(PixelState::kValid),
                kFlying = static_cast<int>(PixelState::kFlying),
                kInconsistent = static_cast<int>(PixelState::kInconsistent);
  std::uint8_t stranded[2][kWidthPx] = {};
  auto strand_one = [&](int i) {
    if (st[i] != PixelState::kValid) return false;
    const float ri = r[i], th = flying_threshold_m(ri);
    bool agrees = false, edge = false;
    for (const int j : {i - 1, i + 1, i - w, i + w}) {
      if (st[j] == PixelState::kValid) {
        const bool jump = std::fabs(ri - r[j]) > th;
        agrees = agrees || !jump;
        edge = edge || jump;
      } else {
        edge = edge || st[j] == PixelState::kFlying || st[j] == PixelState::kInconsistent;
      }
    }
    return edge && !agrees;
  };
  auto apply_row = [&](int row) {
    const std::uint8_t* flags = stranded[row & 1];
    for (int col = 1; col < w - 1; ++col) {
      if (flags[col]) state_[row * w + col] = PixelState::kFlying;
    }
  };
  for (int row = 1; row < h - 1; ++row) {
    std::uint8_t* flags = stranded[row & 1];
    int col = 1;
    for (; col + 4 <= w - 1; col += 4) {
      const int i = row * w + col;
      const Ints4 valid = v4::load_bytes(st + i) == kValid;
      const Floats4 ri = v4::load(r + i), th = flying_threshold_m(ri);
      Ints4 agrees = Ints4{0, 0, 0, 0}, edge = Ints4{0, 0, 0, 0};
      auto look_at = [&](int offset) {
        const Ints4 sn = v4::load_bytes(st + i + offset);
        const Ints4 present = sn == kValid;
        const Ints4 jump = v4::abs4(ri - v4::load(r + i + offset)) > th;
        agrees |= present & ~jump;
        edge |= (present & jump) | (sn == kFlying) | (sn == kInconsistent);
      };
      look_at(-1);
      look_at(1);
      look_at(-w);
      look_at(w);
      const Ints4 out = valid & edge & ~agrees;
      for (int k = 0; k < 4; ++k) flags[col + k] = out[k] != 0;
    }
    for (; col < w - 1; ++col) flags[col] = strand_one(row * w + col);
    if (row > 1) apply_row(row - 1);
  }
  apply_row(h - 2);
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
