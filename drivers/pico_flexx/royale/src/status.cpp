#include "royale/Status.hpp"

namespace royale {

royale::String getStatusString(royale::CameraStatus status) {
  switch (status) {
    case CameraStatus::DUTYCYCLE_NOT_SUPPORTED:
      return "DUTYCYCLE_NOT_SUPPORTED";
    case CameraStatus::SPECTRE_NOT_INITIALIZED:
      return "SPECTRE_NOT_INITIALIZED";
    case CameraStatus::NO_USE_CASES:
      return "NO_USE_CASES";
    case CameraStatus::NO_USE_CASES_FOR_LEVEL:
      return "NO_USE_CASES_FOR_LEVEL";
    case CameraStatus::FSM_INVALID_TRANSITION:
      return "FSM_INVALID_TRANSITION";
    case CameraStatus::UNKNOWN:
      return "UNKNOWN";
    default:
      break;
  }
  return hal::to_string(static_cast<hal::CameraStatus>(static_cast<int>(status)));
}

}  // namespace royale
