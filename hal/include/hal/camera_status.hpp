#pragma once
// Status codes of the depth-camera interface. The numeric values are the
// royale SDK's, so logs read the same as with the vendor's tools.
#include <cstdint>

namespace hal {

enum class CameraStatus : std::uint16_t {
  kSuccess = 0,
  kRuntimeError = 1024,
  kDisconnected = 1026,
  kInvalidValue = 1027,
  kTimeout = 1028,
  kLogicError = 2048,
  kNotImplemented = 2049,
  kOutOfBounds = 2050,
  kResourceError = 4096,
  kFileNotFound = 4097,
  kCouldNotOpen = 4098,
  kDataNotFound = 4099,
  kDeviceIsBusy = 4100,
  kUseCaseNotSupported = 5001,
  kFrameRateNotSupported = 5002,
  kExposureTimeNotSupported = 5003,
  kDeviceNotInitialized = 5004,
  kCalibrationDataError = 5005,
  kInsufficientPrivileges = 5006,
  kDeviceAlreadyInitialized = 5007,
  kExposureModeInvalid = 5008,
  kNoCalibrationData = 5009,
  kInsufficientBandwidth = 5010,
};

// Never null; unknown values give "UNKNOWN_STATUS".
const char* to_string(CameraStatus status);

}  // namespace hal
