#pragma once
// One depth frame as royale delivers it to an IDepthDataListener: a dense
// point cloud, row major, width x height points in the camera's optical
// frame (metres). The frame belongs to the camera and is valid only during
// the onNewData call that receives it.
#include <chrono>
#include <cstdint>

#include "royale/Definitions.hpp"

namespace royale {

struct DepthPoint {
  float x;                  // m, right
  float y;                  // m, down
  float z;                  // m, along the optical axis
  float noise;              // m, the depth's standard deviation
  uint16_t grayValue;       // amplitude
  uint8_t depthConfidence;  // 0: invalid; 1 .. 255 rising with confidence
};

struct DepthData {
  int version;                                // of this structure's layout
  std::chrono::microseconds timeStamp;        // capture time since the 1970 epoch
  royale::StreamId streamId;                  // the stream that produced it
  uint16_t width;                             // points per row
  uint16_t height;                            // rows
  royale::Vector<uint32_t> exposureTimes;     // us, one per modulation frequency
  royale::Vector<royale::DepthPoint> points;  // width * height
};

}  // namespace royale
