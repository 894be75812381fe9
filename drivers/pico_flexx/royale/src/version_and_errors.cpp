#include "royale.hpp"

namespace royale {

// The royale release whose level-1 calls this library follows (a part of
// them: drivers/pico_flexx/doc/royale.md); no build number, no revision.
void getVersion(unsigned& major, unsigned& minor, unsigned& patch) {
  major = 3;
  minor = 21;
  patch = 0;
}

void getVersion(unsigned& major, unsigned& minor, unsigned& patch, unsigned& build) {
  getVersion(major, minor, patch);
  build = 0;
}

void getVersion(unsigned& major, unsigned& minor, unsigned& patch, unsigned& build,
                royale::String& scmRevision) {
  getVersion(major, minor, patch, build);
  scmRevision.clear();
}

royale::String getErrorString(royale::CameraStatus status) {
  switch (status) {
    case CameraStatus::SUCCESS:
      return "The call succeeded.";
    case CameraStatus::RUNTIME_ERROR:
      return "Something failed while the call ran (a USB transfer, the processing).";
    case CameraStatus::DISCONNECTED:
      return "The camera is not connected, or was lost.";
    case CameraStatus::INVALID_VALUE:
      return "An argument is not valid (a null listener, an unknown stream id).";
    case CameraStatus::TIMEOUT:
      return "The camera did not answer in time.";
    case CameraStatus::LOGIC_ERROR:
      return "The call does not fit the device's state (capture without a listener).";
    case CameraStatus::NOT_IMPLEMENTED:
      return "This implementation does not offer the call.";
    case CameraStatus::OUT_OF_BOUNDS:
      return "A value lies outside its allowed range.";
    case CameraStatus::RESOURCE_ERROR:
      return "A resource (memory, a USB handle) could not be had.";
    case CameraStatus::FILE_NOT_FOUND:
      return "A file was not found.";
    case CameraStatus::COULD_NOT_OPEN:
      return "The camera or a file could not be opened.";
    case CameraStatus::DATA_NOT_FOUND:
      return "Data the call needs is missing.";
    case CameraStatus::DEVICE_IS_BUSY:
      return "The camera is busy (another process may hold it).";
    case CameraStatus::USECASE_NOT_SUPPORTED:
      return "The camera has no use case of that name.";
    case CameraStatus::FRAMERATE_NOT_SUPPORTED:
      return "The use case does not allow that frame rate.";
    case CameraStatus::EXPOSURE_TIME_NOT_SUPPORTED:
      return "The exposure time lies outside the use case's limits.";
    case CameraStatus::DEVICE_NOT_INITIALIZED:
      return "initialize() must succeed before this call.";
    case CameraStatus::CALIBRATION_DATA_ERROR:
      return "The camera's calibration could not be read or used.";
    case CameraStatus::INSUFFICIENT_PRIVILEGES:
      return "The call needs a higher access level.";
    case CameraStatus::DEVICE_ALREADY_INITIALIZED:
      return "initialize() was already called.";
    case CameraStatus::EXPOSURE_MODE_INVALID:
      return "The exposure mode does not allow this (manual exposure while automatic).";
    case CameraStatus::NO_CALIBRATION_DATA:
      return "The camera holds no calibration.";
    case CameraStatus::INSUFFICIENT_BANDWIDTH:
      return "The USB link is too slow for the use case.";
    case CameraStatus::DUTYCYCLE_NOT_SUPPORTED:
      return "The illumination's duty cycle cannot be set to that.";
    case CameraStatus::SPECTRE_NOT_INITIALIZED:
      return "The vendor's processing was not set up.";
    case CameraStatus::NO_USE_CASES:
      return "The camera offers no use case.";
    case CameraStatus::NO_USE_CASES_FOR_LEVEL:
      return "The camera offers no use case at this access level.";
    case CameraStatus::FSM_INVALID_TRANSITION:
      return "The camera's state machine does not allow this step now.";
    case CameraStatus::UNKNOWN:
      return "An error of no known kind.";
  }
  return "An unknown status.";
}

}  // namespace royale
