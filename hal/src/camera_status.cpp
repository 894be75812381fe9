#include "hal/camera_status.hpp"

namespace hal {

const char* to_string(CameraStatus status) {
  switch (status) {
    case CameraStatus::kSuccess:
      return "SUCCESS";
    case CameraStatus::kRuntimeError:
      return "RUNTIME_ERROR";
    case CameraStatus::kDisconnected:
      return "DISCONNECTED";
    case CameraStatus::kInvalidValue:
      return "INVALID_VALUE";
    case CameraStatus::kTimeout:
      return "TIMEOUT";
    case CameraStatus::kLogicError:
      return "LOGIC_ERROR";
    case CameraStatus::kNotImplemented:
      return "NOT_IMPLEMENTED";
    case CameraStatus::kOutOfBounds:
      return "OUT_OF_BOUNDS";
    case CameraStatus::kResourceError:
      return "RESOURCE_ERROR";
    case CameraStatus::kFileNotFound:
      return "FILE_NOT_FOUND";
    case CameraStatus::kCouldNotOpen:
      return "COULD_NOT_OPEN";
    case CameraStatus::kDataNotFound:
      return "DATA_NOT_FOUND";
    case CameraStatus::kDeviceIsBusy:
      return "DEVICE_IS_BUSY";
    case CameraStatus::kUseCaseNotSupported:
      return "USECASE_NOT_SUPPORTED";
    case CameraStatus::kFrameRateNotSupported:
      return "FRAMERATE_NOT_SUPPORTED";
    case CameraStatus::kExposureTimeNotSupported:
      return "EXPOSURE_TIME_NOT_SUPPORTED";
    case CameraStatus::kDeviceNotInitialized:
      return "DEVICE_NOT_INITIALIZED";
    case CameraStatus::kCalibrationDataError:
      return "CALIBRATION_DATA_ERROR";
    case CameraStatus::kInsufficientPrivileges:
      return "INSUFFICIENT_PRIVILEGES";
    case CameraStatus::kDeviceAlreadyInitialized:
      return "DEVICE_ALREADY_INITIALIZED";
    case CameraStatus::kExposureModeInvalid:
      return "EXPOSURE_MODE_INVALID";
    case CameraStatus::kNoCalibrationData:
      return "NO_CALIBRATION_DATA";
    case CameraStatus::kInsufficientBandwidth:
      return "INSUFFICIENT_BANDWIDTH";
  }
  return "UNKNOWN_STATUS";
}

}  // namespace hal
