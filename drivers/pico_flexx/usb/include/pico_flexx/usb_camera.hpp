#pragma once
// The Pico Flexx over USB on libusb-1.0 (PROTOCOL.md beside this library).
//
// - open(): the first camera whose vendor and product are in the
//   configuration's list (and whose serial matches, when one is given);
//   open, claim interface 0, IDENTIFY. An event thread then handles
//   libusb's events until close().
// - Commands are synchronous, one at a time, each with a timeout; a reply
//   that never comes is kTimeout, a refusal kRefused with the camera's
//   status kept (last_refusal()).
// - Streaming: a fixed pool of asynchronous bulk transfers (transfer_bytes,
//   16 KB or more, each) on the stream endpoint, resubmitted as they
//   complete; FrameAssembler checks header, size, checksum and sequence;
//   only whole, checked frames reach the RawFrameListener, on the event
//   thread. Nothing is allocated per frame (libusb's Linux backend itself
//   callocs one URB array per submitted transfer).
// - Faults: an unplug (hotplug "left", or transfers ending with no device)
//   closes the handle and waits for the camera to come back (hotplug
//   "arrived", or a search every reconnect_poll_ms), then re-initialises
//   and streams again. A stalled stream, failing transfers or silence (no
//   bytes at all) climb a ladder: clear the halt, re-initialise the camera,
//   reset the device. A camera whose bytes still arrive is never silent:
//   when none of its frames passes the checks it is reported as a corrupt
//   stream (StreamHealth), and the ladder is left alone. A good frame puts
//   the ladder back at its foot.
// - Lost: past the ladder's top, or unplugged past reconnect_window_ms.
//   The driver still looks for the camera, with a back-off from
//   reconnect_poll_ms up to reacquire_max_interval_ms (and at once on
//   hotplug "arrived"), and streams again once bytes arrive.
// Robot code: no exceptions, every loop bounded, all memory at construction.
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <mutex>
#include <thread>

#include "hal/clock.hpp"
#include "pico_flexx/capture_clock_map.hpp"
#include "pico_flexx/frame_assembler.hpp"
#include "pico_flexx/usb_protocol.hpp"
#include "tof/raw_frame.hpp"

struct libusb_context;
struct libusb_device;
struct libusb_device_handle;
struct libusb_transfer;

namespace pico_flexx {

enum class UsbStatus : std::uint8_t {
  kOk,
  kNotFound,      // no matching camera on the bus
  kNoDevice,      // the camera went away
  kAccessDenied,  // the device node's permissions
  kBusy,          // the interface is claimed by someone else
  kTimeout,       // no reply within the command's timeout
  kStall,         // an endpoint halted
  kIoError,       // a transfer failed otherwise
  kBadReply,      // a reply that does not parse (parse_status() says why)
  kRefused,       // the camera answered with an error (last_refusal())
  kNotOpen,
  kStreaming,  // not while streaming
  kNotStreaming,
  kBadArgument,
  kNoMemory,     // at construction: a buffer or transfer not allocated
  kLibusbError,  // libusb failed to start
};
const char* to_string(UsbStatus status);

enum class CameraState : std::uint8_t {
  kClosed,
  kOpen,  // open, not streaming
  kStreaming,
  kRecovering,        // climbing the ladder
  kWaitingForDevice,  // unplugged; looking for it to come back
  kLost,              // past the ladder or the reconnect window (lost_reason()); still looking
};
const char* to_string(CameraState state);

enum class LostReason : std::uint8_t {
  kNone,
  kUnplugged,       // not back within reconnect_window_ms
  kStalled,         // the stream kept stalling through the ladder
  kSilent,          // no bytes through the ladder
  kTransferErrors,  // transfers kept failing through the ladder
  kReinitFailed,    // a rung itself failed (the camera refused its settings, a reset failed)
};
const char* to_string(LostReason reason);

// How the stream is doing, judged over the silence window.
enum class StreamHealth : std::uint8_t {
  kNotStreaming,
  kOk,              // good frames arrive
  kCorruptStream,   // bytes arrive, but no frame passes the checks
  kSilent,          // no bytes (the ladder climbs)
  kStalled,         // the stream endpoint halted (the ladder climbs)
  kTransferErrors,  // transfers failed (the ladder climbs)
  kNoDevice,        // unplugged, or lost and not found again yet
};
const char* to_string(StreamHealth health);

struct UsbId {
  std::uint16_t vendor_id;
  std::uint16_t product_id;
};

struct UsbCameraConfig {
  static constexpr std::size_t kMaxIds = 4;
  UsbId ids[kMaxIds] = {{kVendorId, kProductId}};
  std::size_t id_count = 1;
  char serial[kSerialBytes + 1] = {};  // empty: the first camera found
  int command_timeout_ms = 200;
  std::size_t transfer_bytes = 64 * 1024;  // a multiple of 512, >= 16 KB
  int transfer_count = 8;                  // 1 .. kMaxTransfers
  // Streaming with no good frame for this long climbs the ladder; it is
  // also at least four frame periods of the use case.
  int silence_ms = 500;
  int reconnect_poll_ms = 100;
  int reconnect_window_ms = 10000;
  // Once lost, searches back off from reconnect_poll_ms, doubling up to this.
  int reacquire_max_interval_ms = 2000;
  std::uint8_t use_case_index = 5;  // applied at open and after every reconnect
  bool exposure_automatic = false;
  std::uint32_t exposure_us = 0;  // 0: the camera's own
};
constexpr int kMaxTransfers = 32;

struct UsbCounters {
  std::uint64_t commands = 0;
  std::uint64_t command_timeouts = 0;
  std::uint64_t command_refusals = 0;
  std::uint64_t command_errors = 0;  // transfer errors, bad replies
  std::uint64_t stale_replies = 0;   // late replies to an earlier command, discarded
  std::uint64_t transfers_submitted = 0;
  std::uint64_t transfers_completed = 0;
  std::uint64_t transfers_failed = 0;
  std::uint64_t transfers_cancelled = 0;
  std::uint64_t bytes_received = 0;
  std::uint64_t frames_delivered = 0;
  std::uint64_t stalls = 0;
  std::uint64_t silences = 0;
  std::uint64_t clear_halts = 0;
  std::uint64_t reinitialisations = 0;
  std::uint64_t usb_resets = 0;
  std::uint64_t unplugs = 0;
  std::uint64_t replugs = 0;
  std::uint64_t corrupt_streams = 0;         // times the stream became CORRUPT_STREAM
  std::uint64_t consecutive_bad_frames = 0;  // refused since the last good frame
  std::uint64_t reacquire_attempts = 0;      // searches while lost
  std::uint64_t reacquisitions = 0;          // lost, then streaming (or open) again
  AssemblerCounts assembly;
  // From the callback of a frame's last transfer to the listener's return
  // (microseconds; the listener's own time included), of the last frame.
  std::int64_t last_delivery_us = 0;
};

// What the driver knows of a delivered frame besides its samples.
struct RawFrameInfo {
  std::uint32_t sequence = 0;
  std::uint8_t use_case_index = 0;
  std::int64_t first_transfer_us = 0;  // when its first transfer (the header) completed
  std::int64_t last_transfer_us = 0;   // when its last transfer completed (the clock's)
  std::int64_t camera_time_us = 0;     // its capture time in the header, the camera's clock
  // The capture time on the clock's time base (the frame's capture_time_us):
  // the header's, moved by the least delay to the first transfer
  // (capture_clock_map.hpp); and that bound's change over the last window.
  std::int64_t capture_time_us = 0;
  std::int64_t clock_window_change_us = 0;
};

class RawFrameListener {
 public:
  virtual ~RawFrameListener() = default;
  // On the event thread, once per whole, checked frame; `frame` is valid
  // during the call only. Must not block long: transfers wait meanwhile.
  virtual void on_raw_frame(const RawFrameInfo& info, const tof::RawFrame& frame) = 0;
};

// The header's stamps are the camera's clock, never the host's, however
// near they lie (a camera powered up a moment before the host's clock
// read the same).
inline CaptureClockMapConfig camera_clock_map_config() {
  CaptureClockMapConfig c;
  c.same_clock_window_us = -1;
  return c;
}

class UsbCamera {
 public:
  // Allocates every buffer and transfer; init_status() says whether it could.
  UsbCamera(const UsbCameraConfig& config, const hal::Clock& clock);
  ~UsbCamera();
  UsbCamera(const UsbCamera&) = delete;
  UsbCamera& operator=(const UsbCamera&) = delete;

  UsbStatus init_status() const { return init_status_; }

  [[nodiscard]] UsbStatus open();
  void close();

  [[nodiscard]] UsbStatus identify(Identity* out);
  // The calibration file's bytes, CRC checked, read in 4 KB chunks.
  [[nodiscard]] UsbStatus read_calibration(std::uint8_t* out, std::size_t capacity,
                                           std::size_t* bytes);
  [[nodiscard]] UsbStatus set_use_case(std::uint8_t use_case_index);
  [[nodiscard]] UsbStatus set_exposure_mode(bool automatic);
  [[nodiscard]] UsbStatus set_exposure_time(std::uint32_t exposure_us);

  // `listener` (not owned) receives frames until stop_streaming().
  [[nodiscard]] UsbStatus start_streaming(RawFrameListener* listener);
  [[nodiscard]] UsbStatus stop_streaming();

  CameraState state() const { return state_.load(); }
  LostReason lost_reason() const { return lost_reason_.load(); }
  StreamHealth health() const { return health_.load(); }
  // start_streaming() was called and stop_streaming() not since: frames are
  // wanted, whether they flow or the driver is bringing the camera back.
  bool capture_requested() const { return want_streaming_.load(); }
  UsbCounters counters() const;
  ReplyStatus last_refusal() const { return last_refusal_.load(); }
  ParseStatus last_parse_status() const { return last_parse_.load(); }
  Command last_failed_command() const { return last_failed_command_.load(); }
  const Identity& identity() const { return identity_; }

  // libusb's hotplug callback lands here (on whichever thread handles
  // events): it only notes the event for the event thread.
  void note_hotplug(libusb_device* device, bool left);
  std::uint8_t use_case_index() const { return config_.use_case_index; }

 private:
  static void stream_callback(libusb_transfer* transfer);
  void on_stream_transfer(libusb_transfer* transfer);
  void event_loop();
  void note_stream_completion(const libusb_transfer* transfer, std::int64_t now_us);
  void supervise(std::int64_t now_us);
  void supervise_stream(std::int64_t now_us);
  std::int64_t silence_window_us() const;
  void check_stream_liveness(std::int64_t now_us);
  void report_corrupt_stream();
  UsbStatus find_and_open();
  void close_handle();
  UsbStatus apply_settings();
  UsbStatus reopen_camera();
  UsbStatus resume_stream(std::int64_t now_us);
  UsbStatus submit_all();
  void cancel_all();
  bool wait_drained(std::int64_t timeout_us);
  bool stop_transfers();
  void climb_ladder(std::int64_t now_us, LostReason cause);
  void become_lost(LostReason reason, std::int64_t now_us);
  void handle_unplug(std::int64_t now_us);
  void try_reconnect(std::int64_t now_us);
  void supervise_lost(std::int64_t now_us);
  void attempt_reacquisition(std::int64_t now_us);
  void finish_reacquisition(std::int64_t now_us);
  UsbStatus reacquire_for_start();
  UsbStatus map_error(int libusb_error);
  UsbStatus command_locked(Command command, const std::uint8_t* payload, std::size_t payload_bytes,
                           ReplyView* reply, int timeout_ms);

  UsbCameraConfig config_;
  const hal::Clock& clock_;
  UsbStatus init_status_ = UsbStatus::kLibusbError;
  libusb_context* ctx_ = nullptr;
  libusb_device_handle* handle_ = nullptr;
  std::atomic<libusb_device*> device_{nullptr};  // referenced while open
  int hotplug_handles_[UsbCameraConfig::kMaxIds] = {};
  int hotplug_count_ = 0;
  Identity identity_;

  // Commands and the handle they use: one at a time.
  std::mutex command_mutex_;
  std::uint8_t tag_ = 0;
  std::unique_ptr<std::uint8_t[]> command_buffer_, reply_buffer_;

  // Streaming, touched by the event thread (and the callbacks it runs).
  libusb_transfer* transfers_[kMaxTransfers] = {};
  std::unique_ptr<std::uint8_t[]> transfer_memory_;
  std::atomic<int> in_flight_{0};
  std::unique_ptr<tof::RawFrame> frame_;
  FrameAssembler assembler_;
  // The camera's capture stamps on the clock's time base; a frame's first
  // transfer's completion (the least delay from capture is the bound).
  CaptureClockMap clock_map_{camera_clock_map_config()};
  std::int64_t frame_first_transfer_us_ = 0;
  RawFrameListener* listener_ = nullptr;
  std::atomic<bool> resubmit_{false};
  // When the last good frame and the last bytes of any kind arrived: the
  // first says whether frames pass, the second whether the camera is alive.
  std::atomic<std::int64_t> last_frame_us_{0}, last_bytes_us_{0};
  std::atomic<bool> bytes_seen_{false};  // bytes since the stream was (re)started
  std::uint64_t consecutive_bad_frames_ = 0;
  int rung_ = 0;
  LostReason ladder_reason_ = LostReason::kNone;
  std::atomic<bool> stalled_pending_{false}, failed_pending_{false}, gone_pending_{false};
  std::int64_t unplugged_since_us_ = 0, next_search_us_ = 0;
  // While lost: the next search, and the back-off interval after it.
  std::int64_t next_reacquire_us_ = 0, reacquire_interval_us_ = 0;

  std::atomic<bool> hotplug_left_{false}, hotplug_arrived_{false};
  std::atomic<bool> want_streaming_{false};
  std::atomic<CameraState> state_{CameraState::kClosed};
  std::atomic<LostReason> lost_reason_{LostReason::kNone};
  std::atomic<StreamHealth> health_{StreamHealth::kNotStreaming};
  std::atomic<ReplyStatus> last_refusal_{ReplyStatus::kOk};
  std::atomic<ParseStatus> last_parse_{ParseStatus::kOk};
  std::atomic<Command> last_failed_command_{Command::kIdentify};

  mutable std::mutex counters_mutex_;
  UsbCounters counters_;

  std::atomic<bool> quit_{false};
  std::thread event_thread_;
};

}  // namespace pico_flexx
