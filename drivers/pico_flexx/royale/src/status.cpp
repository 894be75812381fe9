#include "royale/Status.hpp"

namespace royale {

royale::String getStatusString(royale::CameraStatus status) {
  return hal::to_string(static_cast<hal::CameraStatus>(static_cast<int>(status)));
}

}  // namespace royale
