#pragma once
// The estimator's input: an organized point cloud in the camera's optical
// frame (x right, y down, z forward), metres. Same member layout as royale's
// depth point, but owned by the estimator so that it depends on nothing of
// ours.
#include <cstddef>
#include <cstdint>

namespace estimator {

struct CloudPoint {
  float x_m;
  float y_m;
  float z_m;
  float noise_m;             // depth standard deviation; 0 when unknown
  std::uint16_t gray_value;  // amplitude
  std::uint8_t confidence;   // 0 = invalid
};

struct OrganizedCloud {
  std::uint64_t frame_id = 0;
  std::int64_t capture_time_us = 0;
  std::uint32_t width = 0;
  std::uint32_t height = 0;
  const CloudPoint* points = nullptr;  // row major, width * height

  const CloudPoint& at(int row, int col) const {
    return points[static_cast<std::size_t>(row) * width + static_cast<std::size_t>(col)];
  }
  std::size_t size() const { return static_cast<std::size_t>(width) * height; }
};

// Invalid: confidence 0, any non-finite coordinate, or z <= 0. (x - x is
// NaN exactly when x is NaN or infinite: one test per coordinate, inline,
// since it runs for every pixel of every frame.)
inline bool is_valid_point(const CloudPoint& p) {
  const float check = (p.x_m - p.x_m) + (p.y_m - p.y_m) + (p.z_m - p.z_m);
  return (p.confidence != 0) & (check == 0.0f) & (p.z_m > 0.0f);
}

// Valid and within the range the detector works in. Written with & so that
// the per-pixel passes compile without branches.
inline bool is_usable_point(const CloudPoint& p, float min_range_m, float max_range_m) {
  return is_valid_point(p) & (p.z_m >= min_range_m) & (p.z_m <= max_range_m);
}

}  // namespace estimator
