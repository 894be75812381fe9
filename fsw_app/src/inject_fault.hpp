#pragma once
// The faults of --fault NAME[@S] in a hardware-in-loop run (host builds
// only), each made to happen where it would on the robot: in the simulated
// devices, the world the camera sees, the navigation sensors, or on the
// USB wire where the driver must find it. The run loop only times them.
#include <string>

#include "camera_source.hpp"
#include "hal/clock.hpp"
#include "hil_world.hpp"

namespace fsw_app {

// Injects `fault` (one of those parse_options accepts) now.
// camera_cut: the in-process cameras' stop (nullptr on the USB path, where
// the cable is pulled instead).
void inject_fault(const std::string& fault, const hal::Clock& clock, HilWorld& world,
                  CameraSource& frames, CameraCut* camera_cut);

}  // namespace fsw_app
