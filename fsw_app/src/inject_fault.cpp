#include "inject_fault.hpp"

#include <cstdint>
#include <limits>

namespace fsw_app {

void inject_fault(const std::string& fault, const hal::Clock& clock, HilWorld& world,
                  CameraSource& frames, CameraCut* camera_cut) {
  if (fault == "servo-silent") {
    sim_hal::BusFaults silent;
    silent.no_reply = true;
    world.servos().set_faults(silent);
  } else if (fault == "gripper-overcurrent") {
    world.gripper().set_winding_short(true);
  } else if (fault == "occlude") {
    world.occlude_until(clock.now_us() + 1000000);
  } else if (fault == "handrail-lost") {
    world.occlude_until(std::numeric_limits<std::int64_t>::max());
  } else if (fault == "corrupt-frames") {
    // Over USB the frames are spoilt on the wire, where the driver
    // drops them; otherwise the camera task refuses them.
    if (frames.hil_usb()) {
      frames.hil_usb()->corrupt_next_frames(5);
    } else {
      world.corrupt_next_frames(5);
    }
  } else if (fault == "imu-silent") {
    world.sensors().silence_imu_until(clock.now_us() + 500000);
  } else if (fault == "imu-lost") {
    world.sensors().silence_imu_until(std::numeric_limits<std::int64_t>::max());
  } else if (fault == "gp-jump") {
    world.sensors().jump_gp(Eigen::Vector3d(0.0, 0.2, 0.0));
  } else if (fault == "usb-unplug") {
    frames.hil_usb()->unplug_for(clock.now_us(), 500000);
  } else if (fault == "usb-stall") {
    frames.hil_usb()->stall_stream();
  } else if (fault == "camera-silent" || fault == "camera-lost") {
    const std::int64_t now_us = clock.now_us();
    const std::int64_t out_us =
        fault == "camera-silent" ? 2000000 : std::numeric_limits<std::int64_t>::max() - now_us;
    if (frames.hil_usb()) {
      frames.hil_usb()->unplug_for(now_us, out_us);
    } else if (camera_cut) {
      camera_cut->cut_until(now_us + out_us);
    }
  }
}

}  // namespace fsw_app
