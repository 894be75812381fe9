#pragma once
// Organized PCD v0.7 files (the Point Cloud Library's format) for depth
// frames: written as FIELDS x y z intensity noise confidence, read with any
// field order, extra fields, ascii or binary data. Invalid points are NaN on
// disk; NaN or z = 0 read back as invalid (confidence 0).
#include <cstdint>
#include <string>
#include <vector>

#include "hal/depth_frame.hpp"

namespace hal {

enum class PcdEncoding : std::uint8_t { kAscii, kBinary };

struct PcdFrame {
  std::uint32_t width = 0;
  std::uint32_t height = 0;
  std::vector<DepthPoint> points;  // row major

  DepthFrame view(std::uint64_t frame_id = 0, std::int64_t capture_time_us = 0) const {
    return DepthFrame{frame_id, capture_time_us, width, height, points.data()};
  }
};

// On failure returns false with *error as "PATH: what is wrong".
bool read_pcd(const std::string& path, PcdFrame* out, std::string* error);
bool parse_pcd(const std::string& bytes, const std::string& path, PcdFrame* out,
               std::string* error);

bool write_pcd(const std::string& path, const DepthFrame& frame, PcdEncoding encoding,
               std::string* error);
std::string encode_pcd(const DepthFrame& frame, PcdEncoding encoding);

}  // namespace hal
