#pragma once
// The Pico Flexx as a USB device, emulated with umockdev: a device node
// and sysfs entry with the camera's identity and descriptors (vendor
// 0x1c28, product 0xc012, high speed, one vendor-specific interface, bulk
// OUT 0x01 for commands, bulk IN 0x81 for replies and 0x82 for raw
// frames), whose usbdevfs ioctls are answered here, as they happen, with
// the project's protocol (drivers/pico_flexx/PROTOCOL.md). The unmodified
// libusb code of the driver runs against it.
//
// The process must run under umockdev's preload library (umockdev-wrapper,
// or LD_PRELOAD=libumockdev-preload.so.0): create() refuses otherwise.
// Requests are answered on umockdev's worker thread; frames are made when
// due, at the use case's rate, by a RawFrameSource (the simulator's raw
// renderer, or anything cheaper a test needs). A due frame with no stream
// transfer waiting for it is dropped at the camera, as a real camera's
// FIFO overflows: its sequence number is skipped.
//
// Faults on demand: unplug and replug, a halted stream endpoint, corrupt
// and short frames, frames with a bad header, commands that are never answered, and a slow host
// (replies held back).
#include <cstdint>
#include <memory>
#include <string>

#include "hal/clock.hpp"
#include "hal/use_case.hpp"
#include "tof/raw_frame.hpp"

namespace sim_hal {

// Makes the camera's raw frames.
class RawFrameSource {
 public:
  virtual ~RawFrameSource() = default;
  // Fills `out` (mode, samples, exposure_us, sensor_temperature_c) with the
  // frame `frame_index` of `use_case`, captured at `capture_host_us` (the
  // host clock's time it fell due; it may be sent later). `exposure_us` is
  // the commanded exposure, 0 when the exposure is automatic.
  virtual void fill(std::uint64_t frame_index, std::int64_t capture_host_us,
                    const hal::UseCase& use_case, std::uint32_t exposure_us,
                    tof::RawFrame* out) = 0;
};

struct EmulatedCameraConfig {
  std::string serial = "0005-1234-0042";
  std::uint8_t firmware_major = 1;
  std::uint8_t firmware_minor = 4;
  std::string calibration;  // the raw path's calibration file's bytes
  int use_case_index = 5;   // at power-up: MODE_5_45FPS_500
  std::uint32_t exposure_us = 500;
  // How fast the camera's own clock (its capture stamps, from power-up)
  // runs against the host's, in parts per million: a crystal's error.
  double clock_ppm = 30.0;
};

struct EmulatorCounts {
  std::uint64_t commands = 0;
  std::uint64_t commands_muted = 0;
  std::uint64_t frames_sent = 0;
  std::uint64_t frames_dropped_no_transfer = 0;  // due with no stream transfer waiting
  std::uint64_t frames_corrupted = 0;
  std::uint64_t frames_shortened = 0;
  std::uint64_t headers_corrupted = 0;
  std::uint64_t urbs_submitted = 0;
  std::uint64_t urbs_reaped = 0;
  std::uint64_t urbs_discarded = 0;
  std::uint64_t clear_halts = 0;
  std::uint64_t resets = 0;
  std::uint64_t plugs = 0;
  std::uint64_t unplugs = 0;
  bool streaming = false;
  int use_case_index = 0;
};

class EmulatedPicoFlexx {
 public:
  // nullptr with *error saying why (not under the preload library, the
  // testbed refused the device).
  static std::unique_ptr<EmulatedPicoFlexx> create(const EmulatedCameraConfig& config,
                                                   RawFrameSource* source, const hal::Clock& clock,
                                                   std::string* error);
  ~EmulatedPicoFlexx();
  EmulatedPicoFlexx(const EmulatedPicoFlexx&) = delete;
  EmulatedPicoFlexx& operator=(const EmulatedPicoFlexx&) = delete;

  // Pulls the cable: a "remove" uevent, the device node gone, every open
  // handle answered ENODEV, transfers in flight returned as shut down.
  void unplug();
  // Plugs it back in (a new device address; the camera powers up afresh:
  // power-up use case, not streaming, sequence numbers from 0).
  bool replug(std::string* error);

  // Halts the stream endpoint: its transfers fail with a stall until the
  // host clears the halt (or resets the device). `persistent`: clearing the
  // halt does not help, only a reset.
  void stall_stream(bool persistent = false);
  // Streams without sending frames (a hung imager), through everything the
  // host tries, until set false.
  void set_silent(bool silent);
  // The next `frames` frames: one payload byte flipped after the checksum
  // was computed / cut off after half their bytes.
  void corrupt_next_frames(int frames);
  void shorten_next_frames(int frames);
  // The next `frames` frames: one header byte flipped after the header's
  // CRC was computed (the magic kept), so the host refuses the whole frame.
  void corrupt_next_headers(int frames);
  // Cancels the corrupt, short and bad-header frames still to come.
  void clear_frame_faults();
  // The next `commands` commands are taken and never answered.
  void mute_next_commands(int commands);
  // Replies wait this long before they are sent (0: none).
  void set_reply_delay_us(std::int64_t delay_us);

  EmulatorCounts counts() const;
  // The host clock's time at which frame `sequence` was captured (read out
  // by the imager), for one of the newest 256 frames; false if not known.
  bool capture_time_of(std::uint32_t sequence, std::int64_t* host_us) const;
  // The device node of the current plug, e.g. /dev/bus/usb/001/002.
  std::string device_node() const;

  struct Impl;

 private:
  explicit EmulatedPicoFlexx(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace sim_hal
