#pragma once
// The emulated camera's insides, shared by its USB side
// (emulated_pico_flexx.cpp: testbed, usbdevfs requests, transfer queues)
// and its camera side (emulated_camera_logic.cpp: commands, frames).
#include <linux/ioctl.h>
#include <linux/usbdevice_fs.h>

#include <array>
#include <cstdint>
#include <deque>
#include <mutex>
#include <string>
#include <vector>

#include "pico_flexx/usb_protocol.hpp"
#include "sim_hal/emulated_pico_flexx.hpp"

typedef struct _UMockdevTestbed UMockdevTestbed;
typedef struct _UMockdevIoctlBase UMockdevIoctlBase;

namespace sim_hal {

// One plug of the cable: the handler attached to its device node. Handles
// of an earlier plug keep their context, which answers ENODEV.
struct PlugContext {
  EmulatedPicoFlexx::Impl* impl = nullptr;
  int generation = 0;
  UMockdevIoctlBase* handler = nullptr;
  std::string node;     // /dev/bus/usb/001/NNN
  std::string syspath;  // the testbed's sysfs path
};

struct EmulatedPicoFlexx::Impl {
  EmulatedCameraConfig config;
  RawFrameSource* source = nullptr;
  const hal::Clock* clock = nullptr;
  UMockdevTestbed* testbed = nullptr;
  std::vector<PlugContext*> plugs;  // every plug so far; the last is current

  mutable std::mutex mutex;  // everything below; the handler runs on umockdev's thread
  int generation = 0;        // the current plug's; a handler of another answers ENODEV
  bool plugged = false;
  EmulatorCounts counts;

  // Transfers the host has submitted and not yet reaped, per endpoint, and
  // those finished and waiting to be reaped (in order).
  std::deque<usbdevfs_urb*> command_urbs, reply_urbs, stream_urbs, done_urbs;

  // Camera state.
  bool streaming = false;
  bool exposure_automatic = false;
  std::uint32_t exposure_us = 0;
  int use_case_index = 0;
  std::uint32_t sequence = 0;
  std::int64_t stream_start_us = 0;
  std::uint64_t frames_due_so_far = 0;  // frames since streaming began
  bool stream_halted = false;
  bool halt_persistent = false;  // CLEAR_HALT does not help, RESET does
  bool silent = false;           // no frames, whatever the host does
  // The camera's own clock: microseconds since its power-up (the host's
  // time then), running config.clock_ppm fast; and the host's time of the
  // newest frames' captures, by sequence number, for tests to compare with.
  std::int64_t power_up_us = 0;
  static constexpr std::size_t kCaptureLog = 256;
  std::array<std::pair<std::uint32_t, std::int64_t>, kCaptureLog> capture_log{};
  std::size_t captures_logged = 0;

  // Replies waiting for a reply transfer: the bytes and when they may go.
  struct PendingReply {
    std::vector<std::uint8_t> bytes;
    std::int64_t ready_us = 0;
  };
  std::deque<PendingReply> replies;

  // The frame being sent: header and payload, how far it has gone, and
  // whether a zero-length transfer must end it.
  tof::RawFrame raw;
  std::vector<std::uint8_t> frame_bytes;
  std::size_t frame_length = 0;
  std::size_t frame_sent = 0;
  bool frame_active = false;
  bool zero_length_pending = false;

  // Faults.
  int corrupt_frames = 0;
  int short_frames = 0;
  int corrupt_headers = 0;
  int muted_commands = 0;
  std::int64_t reply_delay_us = 0;

  // USB side (emulated_pico_flexx.cpp).
  bool add_device(std::string* error);
  // Camera side (emulated_camera_logic.cpp); called with `mutex` held.
  void power_up();
  void execute_command(const std::uint8_t* data, std::size_t length);
  // Moves finished transfers to done_urbs: replies, stream data.
  void advance(std::int64_t now_us);

 private:
  void queue_reply(pico_flexx::Command command, std::uint8_t tag, pico_flexx::ReplyStatus status,
                   const std::uint8_t* payload, std::size_t payload_bytes);
  void begin_frame(std::int64_t capture_host_us);
  void feed_stream();
  void feed_replies(std::int64_t now_us);
};

}  // namespace sim_hal
