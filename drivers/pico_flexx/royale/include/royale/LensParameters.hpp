#pragma once
// The camera's intrinsics as royale reports them: pinhole plus
// Brown-Conrady distortion, from the unit's calibration.
#include "royale/Definitions.hpp"

namespace royale {

struct LensParameters {
  royale::Pair<float, float> principalPoint;        // cx, cy (px)
  royale::Pair<float, float> focalLength;           // fx, fy (px)
  royale::Pair<float, float> distortionTangential;  // p1, p2
  royale::Vector<float> distortionRadial;           // k1, k2, k3
};

}  // namespace royale
