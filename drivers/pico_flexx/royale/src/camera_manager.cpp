#include "royale/CameraManager.hpp"

#include <algorithm>
#include <cstring>

#include "pico_flexx/usb_camera.hpp"
#include "pico_flexx_device.hpp"

namespace royale {

CameraManager::CameraManager(const royale::String&) {}

royale::Vector<royale::String> CameraManager::getConnectedCameraList() {
  listed_.clear();
  // The driver opens the first camera that answers IDENTIFY; its identity
  // carries the serial, which is the camera's id.
  hal::MonotonicClock clock;
  pico_flexx::UsbCamera probe(pico_flexx::UsbCameraConfig{}, clock);
  if (probe.open() == pico_flexx::UsbStatus::kOk) {
    listed_.push_back(probe.identity().serial);
    probe.close();
  }
  return listed_;
}

std::unique_ptr<royale::ICameraDevice> CameraManager::createCamera(const royale::String& cameraId) {
  const bool listed = std::find(listed_.begin(), listed_.end(), cameraId) != listed_.end();
  if (!listed || cameraId.empty() || cameraId.size() > pico_flexx::kSerialBytes) return nullptr;
  pico_flexx::UsbCameraConfig usb;
  std::memcpy(usb.serial, cameraId.c_str(), cameraId.size() + 1);
  return std::make_unique<PicoFlexxDevice>(usb, cameraId);
}

}  // namespace royale
