#pragma once
#include "royale/DepthData.hpp"

namespace royale {

class IDepthDataListener {
 public:
  virtual ~IDepthDataListener() = default;
  // On the camera's thread, once per frame; `data` is valid during the call
  // only. Must not block, and must not call the camera back.
  virtual void onNewData(const royale::DepthData* data) = 0;
};

}  // namespace royale
