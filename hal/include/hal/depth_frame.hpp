#pragma once
// A depth frame in the layout of royale's DepthData: row-major points in the
// camera's optical frame (x right, y down, z forward), metres.
#include <cstddef>
#include <cstdint>

namespace hal {

struct DepthPoint {
  float x_m;
  float y_m;
  float z_m;
  float noise_m;             // standard deviation of the depth measurement
  std::uint16_t gray_value;  // amplitude
  std::uint8_t confidence;   // 0 = invalid, 255 = full confidence
};

// Pinhole model with Brown-Conrady distortion, as royale reports it.
struct LensParameters {
  double cx_px = 0.0, cy_px = 0.0;      // principal point
  double fx_px = 0.0, fy_px = 0.0;      // focal lengths
  double k1 = 0.0, k2 = 0.0, k3 = 0.0;  // radial
  double p1 = 0.0, p2 = 0.0;            // tangential
};

// A view of one frame. The points belong to whoever delivers the frame and
// stay valid only during the listener call that receives it.
struct DepthFrame {
  std::uint64_t frame_id = 0;
  std::int64_t capture_time_us = 0;  // monotonic clock of the delivering host
  std::uint32_t width = 0;
  std::uint32_t height = 0;
  const DepthPoint* points = nullptr;  // width * height, row major

  const DepthPoint& at(std::uint32_t row, std::uint32_t col) const {
    return points[static_cast<std::size_t>(row) * width + col];
  }
};

// A point is usable when the sensor marked it valid and its coordinates are
// finite with positive depth (recordings mark invalid points with NaN or 0).
bool is_valid(const DepthPoint& p);

// Number of valid points in the frame.
std::size_t count_valid(const DepthFrame& frame);

}  // namespace hal
