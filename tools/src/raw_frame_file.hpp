#pragma once
// hrsim's raw-frame file (frame_NNNNN.raw): one tof::RawFrame as the
// imager read it out, so that the robot's ToF processing can be run on it
// again. Little-endian:
//
//   offset  size  field
//   0       8     magic "HRPRAW1\n"
//   8       4     uint32 width (224)
//   12      4     uint32 height (171)
//   16      4     uint32 raw images that follow (9 for MODE_9, 5 for MODE_5)
//   20      4     uint32 exposure per phase image, microseconds
//   24      8     uint64 frame id
//   32      8     int64 capture time, microseconds
//   40      4     float32 imager temperature, deg C
//   44      4     uint32 0 (reserved)
//   48      ...   images * width * height uint16 samples (12-bit, 0..4095),
//                 planar in the imager's order: per frequency the phase steps
//                 0, 90, 180, 270 deg, then the grey image; each row major.
//
// Version 1 (the magic's digit). A MODE_9 frame is 689 520 bytes.
#include <string>

#include "tof/raw_frame.hpp"

namespace tools {

bool write_raw_frame(const std::string& path, const tof::RawFrame& frame, std::string* error);
// Reads a file written by write_raw_frame; false with *error naming the
// path and what is wrong (magic, size, image count, a sample above 4095).
bool read_raw_frame(const std::string& path, tof::RawFrame* frame, std::string* error);

}  // namespace tools
