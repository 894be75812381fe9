#pragma once
// Finds the cameras on the bus and creates their devices, as royale's
// CameraManager does. Cameras are named by their serial number.
#include <memory>

#include "royale/Definitions.hpp"
#include "royale/ICameraDevice.hpp"

namespace royale {

class CameraManager {
 public:
  // royale's activation code unlocks access levels above 1; this
  // implementation has level 1 only and ignores it.
  explicit CameraManager(const royale::String& activationCode = "");

  // The ids of the Pico Flexx cameras it can open (vendor 0x1c28, product
  // 0xc012). Opens each briefly to read its serial; a camera another
  // process holds is not listed. Today: the first camera found.
  royale::Vector<royale::String> getConnectedCameraList();

  // A device for an id of the last list; nullptr for any other id.
  std::unique_ptr<royale::ICameraDevice> createCamera(const royale::String& cameraId);

 private:
  royale::Vector<royale::String> listed_;
};

}  // namespace royale
