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
  // driver's own account: the gaps in the sequence of frames handed on,
  // which hold the frames the camera made and could not send (no transfer
  // was waiting) and the frames the driver refused (short, corrupt, out of
  // order). Frames not made while the cable was out are not counted (the
  // camera was not streaming), nor a refused frame no good frame followed.
  std::uint64_t frames_lost = 0;
  std::uint64_t frames_refused = 0;   // of frames_lost
  std::uint64_t frames_not_sent = 0;  // of frames_lost
  std::string state;                  // the driver's camera state at the end (STREAMING, LOST, ...)
  std::string health;                 // its stream's health then (OK, SILENT, CORRUPT_STREAM, ...)
  // The emulated camera's own count of frames it made (sent and dropped
  // for want of a transfer); -1 for a real camera.
  std::int64_t frames_made_by_camera = -1;
};

inline UsbPathReport usb_path_report(const pico_flexx::UsbCamera& usb) {
  UsbPathReport r;
  r.driver = usb.counters();
  const pico_flexx::AssemblerCounts& a = r.driver.assembly;
  r.frames_lost = a.frames_missed;
  r.frames_refused = a.dropped();
  r.frames_not_sent = a.frames_missed > a.dropped() ? a.frames_missed - a.dropped() : 0;
  r.state = pico_flexx::to_string(usb.state());
  r.health = pico_flexx::to_string(usb.health());
  return r;
}

}  // namespace fsw_app
