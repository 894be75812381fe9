#pragma once
// royale::CameraStatus: royale's names, with the values the project keeps
// once, in hal/camera_status.hpp (royale's own numbers).
#include "hal/camera_status.hpp"
#include "royale/Definitions.hpp"

namespace royale {

namespace detail {
constexpr int status_value(hal::CameraStatus status) {
  return static_cast<int>(status);
}
}  // namespace detail

enum class CameraStatus {
  SUCCESS = detail::status_value(hal::CameraStatus::kSuccess),
  RUNTIME_ERROR = detail::status_value(hal::CameraStatus::kRuntimeError),
  DISCONNECTED = detail::status_value(hal::CameraStatus::kDisconnected),
  INVALID_VALUE = detail::status_value(hal::CameraStatus::kInvalidValue),
  TIMEOUT = detail::status_value(hal::CameraStatus::kTimeout),
  LOGIC_ERROR = detail::status_value(hal::CameraStatus::kLogicError),
  NOT_IMPLEMENTED = detail::status_value(hal::CameraStatus::kNotImplemented),
  OUT_OF_BOUNDS = detail::status_value(hal::CameraStatus::kOutOfBounds),
  RESOURCE_ERROR = detail::status_value(hal::CameraStatus::kResourceError),
  FILE_NOT_FOUND = detail::status_value(hal::CameraStatus::kFileNotFound),
  COULD_NOT_OPEN = detail::status_value(hal::CameraStatus::kCouldNotOpen),
  DATA_NOT_FOUND = detail::status_value(hal::CameraStatus::kDataNotFound),
  DEVICE_IS_BUSY = detail::status_value(hal::CameraStatus::kDeviceIsBusy),
  USECASE_NOT_SUPPORTED = detail::status_value(hal::CameraStatus::kUseCaseNotSupported),
  FRAMERATE_NOT_SUPPORTED = detail::status_value(hal::CameraStatus::kFrameRateNotSupported),
  EXPOSURE_TIME_NOT_SUPPORTED = detail::status_value(hal::CameraStatus::kExposureTimeNotSupported),
  DEVICE_NOT_INITIALIZED = detail::status_value(hal::CameraStatus::kDeviceNotInitialized),
  CALIBRATION_DATA_ERROR = detail::status_value(hal::CameraStatus::kCalibrationDataError),
  INSUFFICIENT_PRIVILEGES = detail::status_value(hal::CameraStatus::kInsufficientPrivileges),
  DEVICE_ALREADY_INITIALIZED = detail::status_value(hal::CameraStatus::kDeviceAlreadyInitialized),
  EXPOSURE_MODE_INVALID = detail::status_value(hal::CameraStatus::kExposureModeInvalid),
  NO_CALIBRATION_DATA = detail::status_value(hal::CameraStatus::kNoCalibrationData),
  INSUFFICIENT_BANDWIDTH = detail::status_value(hal::CameraStatus::kInsufficientBandwidth),
  // royale's, which no call here returns (hal has no such cases); kept so
  // that an application's switch over royale's statuses compiles.
  DUTYCYCLE_NOT_SUPPORTED = 5011,
  SPECTRE_NOT_INITIALIZED = 5012,
  NO_USE_CASES = 5013,
  NO_USE_CASES_FOR_LEVEL = 5014,
  FSM_INVALID_TRANSITION = 8096,
  UNKNOWN = 0x7fffff01,  // the catch-all
};

// The status's name ("USECASE_NOT_SUPPORTED"): hal::to_string's for the
// codes hal has, royale's own name for the others.
royale::String getStatusString(royale::CameraStatus status);

}  // namespace royale
