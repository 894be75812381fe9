#pragma once
// What a run reports of the camera's USB path (the Pico Flexx driver on the
// robot, or on the emulated camera in a hardware-in-loop run).
#include <cstdint>
#include <string>

#include "pico_flexx/usb_camera.hpp"

namespace fsw_app {

struct UsbPathReport {
  pico_flexx::UsbCounters driver;
  // Frames the camera made that never reached the processing, in the
  // driver's own account: sequence gaps (made, not sent: no transfer was
  // waiting) and frames it refused (short, corrupt, out of order). Frames
  // not made while the cable was out are not counted: the camera was not
  // streaming then.
  std::uint64_t frames_lost = 0;
  std::string state;  // the driver's camera state at the end (STREAMING, LOST, ...)
  // The emulated camera's own count of frames it made (sent and dropped
  // for want of a transfer); -1 for a real camera.
  std::int64_t frames_made_by_camera = -1;
};

inline UsbPathReport usb_path_report(const pico_flexx::UsbCamera& usb) {
  UsbPathReport r;
  r.driver = usb.counters();
  r.frames_lost = r.driver.assembly.frames_missed + r.driver.assembly.dropped();
  r.state = pico_flexx::to_string(usb.state());
  return r;
}

}  // namespace fsw_app
