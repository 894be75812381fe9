#pragma once
// Organized PCD v0.7 files (the Point Cloud Library's format) for depth
// frames: written as FIELDS x y z intensity noise confidence, read with any
// field order, extra fields, ascii, binary or binary_compressed data (LZF,
// fields stored one after another as PCL does). Invalid points are NaN on
// disk; NaN or z = 0 read back as invalid (confidence 0).
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "hal/depth_frame.hpp"

namespace formats {

enum class PcdEncoding : std::uint8_t { kAscii, kBinary, kBinaryCompressed };

// Limits checked against the header before anything is allocated, so that a
// corrupt or hostile header is refused by name instead of exhausting memory
// (the robot has 512 MB; a Pico Flexx frame is 224 x 171 points).
constexpr std::uint64_t kMaxPcdPoints = 4096ull * 4096ull;
// Largest binary_compressed payload once decompressed.
constexpr std::uint64_t kMaxPcdUncompressedBytes = 256ull << 20;
// Largest file read_pcd reads: that payload plus room for the header.
constexpr std::size_t kMaxPcdFileBytes = (256u << 20) + (1u << 20);

struct PcdFrame {
  std::uint32_t width = 0;
  std::uint32_t height = 0;
  std::vector<hal::DepthPoint> points;  // row major

  hal::DepthFrame view(std::uint64_t frame_id = 0, std::int64_t capture_time_us = 0) const {
    return hal::DepthFrame{frame_id, capture_time_us, width, height, points.data()};
  }
};

// On failure returns false with *error as "PATH: what is wrong"; *out is
// then unchanged. `max_points` is the caller's own limit (its largest
// frame, e.g. the estimator's max_width x max_height), checked against the
// header before the points are allocated.
bool read_pcd(const std::string& path, PcdFrame* out, std::string* error,
              std::uint64_t max_points = kMaxPcdPoints);
bool parse_pcd(const std::string& bytes, const std::string& path, PcdFrame* out, std::string* error,
               std::uint64_t max_points = kMaxPcdPoints);

bool write_pcd(const std::string& path, const hal::DepthFrame& frame, PcdEncoding encoding,
               std::string* error);
// The whole file. Empty only if LZF compression failed (kBinaryCompressed).
std::string encode_pcd(const hal::DepthFrame& frame, PcdEncoding encoding);

}  // namespace formats
