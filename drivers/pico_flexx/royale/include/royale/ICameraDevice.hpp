#pragma once
// The camera device of royale's C++ API, the part applications use (level
// 1 access). Created by CameraManager; nothing throws, every call returns
// a CameraStatus.
#include <cstdint>

#include "royale/CameraAccessLevel.hpp"
#include "royale/Definitions.hpp"
#include "royale/ExposureMode.hpp"
#include "royale/IDepthDataListener.hpp"
#include "royale/IEventListener.hpp"
#include "royale/LensParameters.hpp"
#include "royale/Status.hpp"

namespace royale {

class ICameraDevice {
 public:
  virtual ~ICameraDevice() = default;

  // Opens the camera, reads its calibration, builds the processing. Every
  // other call but getId and getCameraName needs it first.
  virtual royale::CameraStatus initialize() = 0;

  virtual royale::CameraStatus getId(royale::String& id) const = 0;
  virtual royale::CameraStatus getCameraName(royale::String& cameraName) const = 0;

  virtual royale::CameraStatus setUseCase(const royale::String& name) = 0;
  virtual royale::CameraStatus getUseCases(royale::Vector<royale::String>& useCases) const = 0;
  virtual royale::CameraStatus getCurrentUseCase(royale::String& useCase) const = 0;
  // Key and value pairs about the camera: SERIAL_NUMBER, FIRMWARE_VERSION,
  // USB_PROTOCOL_VERSION (needs initialize()).
  virtual royale::CameraStatus getCameraInfo(
      royale::Vector<royale::Pair<royale::String, royale::String>>& camInfo) const = 0;
  // The current use case's streams (one here, 0xdefa), and a use case's
  // number of streams by name.
  virtual royale::CameraStatus getStreams(royale::Vector<royale::StreamId>& streams) const = 0;
  virtual royale::CameraStatus getNumberOfStreams(const royale::String& name,
                                                  uint32_t& nrStreams) const = 0;
  // The frame rate: the use case's own (getMaxFrameRate) unless set lower,
  // 1 up to it, for the current use case (a new use case starts at its
  // own). The camera keeps its use case's rate; the device hands on the
  // frames that fall due at the rate set and skips the others.
  virtual royale::CameraStatus setFrameRate(uint16_t framerate) = 0;
  virtual royale::CameraStatus getFrameRate(uint16_t& frameRate) const = 0;
  virtual royale::CameraStatus getMaxFrameRate(uint16_t& maxFrameRate) const = 0;

  virtual royale::CameraStatus setExposureTime(uint32_t exposureTime,
                                               royale::StreamId streamId = 0) = 0;
  virtual royale::CameraStatus setExposureMode(royale::ExposureMode exposureMode,
                                               royale::StreamId streamId = 0) = 0;
  virtual royale::CameraStatus getExposureMode(royale::ExposureMode& exposureMode,
                                               royale::StreamId streamId = 0) const = 0;
  virtual royale::CameraStatus getExposureLimits(royale::Pair<uint32_t, uint32_t>& exposureLimits,
                                                 royale::StreamId streamId = 0) const = 0;
  // Level 2 (exposure times per sequence): INSUFFICIENT_PRIVILEGES here.
  virtual royale::CameraStatus setExposureTimes(const royale::Vector<uint32_t>& exposureTimes,
                                                royale::StreamId streamId = 0) = 0;

  virtual royale::CameraStatus registerDataListener(royale::IDepthDataListener* listener) = 0;
  virtual royale::CameraStatus unregisterDataListener() = 0;
  // Events (IEvent.hpp) from a thread of the device's: the stream's frame
  // counts about once a second while capturing (RAW_FRAME_STATS, a WARNING
  // when frames were dropped) and a lost camera (DEVICE_DISCONNECTED).
  virtual royale::CameraStatus registerEventListener(royale::IEventListener* listener) = 0;
  virtual royale::CameraStatus unregisterEventListener() = 0;

  virtual royale::CameraStatus startCapture() = 0;
  virtual royale::CameraStatus stopCapture() = 0;

  virtual royale::CameraStatus getMaxSensorWidth(uint16_t& maxSensorWidth) const = 0;
  virtual royale::CameraStatus getMaxSensorHeight(uint16_t& maxSensorHeight) const = 0;
  virtual royale::CameraStatus getLensParameters(royale::LensParameters& param) const = 0;

  virtual royale::CameraStatus isConnected(bool& connected) const = 0;
  virtual royale::CameraStatus isCalibrated(bool& calibrated) const = 0;
  virtual royale::CameraStatus isCapturing(bool& capturing) const = 0;
  // L1 (CameraAccessLevel.hpp).
  virtual royale::CameraStatus getAccessLevel(royale::CameraAccessLevel& accessLevel) const = 0;
};

}  // namespace royale
