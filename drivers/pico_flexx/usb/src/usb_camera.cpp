// The Pico Flexx USB driver: libusb set-up, finding and opening the
// camera, and its commands. Streaming and recovery: usb_stream.cpp.
#include <libusb.h>

#include <cstring>

#include "pico_flexx/usb_camera.hpp"

namespace pico_flexx {
namespace {

// Replies are read into a whole number of 512-byte packets, so that the
// longest never overflows the transfer.
constexpr std::size_t kReplyBufferBytes =
    (kMaxReplyBytes + kBulkPacketBytes - 1) / kBulkPacketBytes * kBulkPacketBytes;
// Late replies discarded before a command gives up on its own.
constexpr int kMaxStaleReplies = 4;

int on_hotplug(libusb_context*, libusb_device* device, libusb_hotplug_event event,
               void* user_data) {
  static_cast<UsbCamera*>(user_data)->note_hotplug(device,
                                                   event == LIBUSB_HOTPLUG_EVENT_DEVICE_LEFT);
  return 0;  // stay registered
}

}  // namespace

const char* to_string(UsbStatus status) {
  switch (status) {
    case UsbStatus::kOk:
      return "OK";
    case UsbStatus::kNotFound:
      return "NOT_FOUND";
    case UsbStatus::kNoDevice:
      return "NO_DEVICE";
    case UsbStatus::kAccessDenied:
      return "ACCESS_DENIED";
    case UsbStatus::kBusy:
      return "BUSY";
    case UsbStatus::kTimeout:
      return "TIMEOUT";
    case UsbStatus::kStall:
      return "STALL";
    case UsbStatus::kIoError:
      return "IO_ERROR";
    case UsbStatus::kBadReply:
      return "BAD_REPLY";
    case UsbStatus::kRefused:
      return "REFUSED";
    case UsbStatus::kNotOpen:
      return "NOT_OPEN";
    case UsbStatus::kStreaming:
      return "STREAMING";
    case UsbStatus::kNotStreaming:
      return "NOT_STREAMING";
    case UsbStatus::kBadArgument:
      return "BAD_ARGUMENT";
    case UsbStatus::kNoMemory:
      return "NO_MEMORY";
    case UsbStatus::kLibusbError:
      return "LIBUSB_ERROR";
  }
  return "UNKNOWN_USB_STATUS";
}

const char* to_string(CameraState state) {
  switch (state) {
    case CameraState::kClosed:
      return "CLOSED";
    case CameraState::kOpen:
      return "OPEN";
    case CameraState::kStreaming:
      return "STREAMING";
    case CameraState::kRecovering:
      return "RECOVERING";
    case CameraState::kWaitingForDevice:
      return "WAITING_FOR_DEVICE";
    case CameraState::kLost:
      return "LOST";
  }
  return "UNKNOWN_CAMERA_STATE";
}

const char* to_string(LostReason reason) {
  switch (reason) {
    case LostReason::kNone:
      return "NONE";
    case LostReason::kUnplugged:
      return "UNPLUGGED";
    case LostReason::kStalled:
      return "STALLED";
    case LostReason::kSilent:
      return "SILENT";
    case LostReason::kTransferErrors:
      return "TRANSFER_ERRORS";
    case LostReason::kReinitFailed:
      return "REINIT_FAILED";
  }
  return "UNKNOWN_LOST_REASON";
}

const char* to_string(StreamHealth health) {
  switch (health) {
    case StreamHealth::kNotStreaming:
      return "NOT_STREAMING";
    case StreamHealth::kOk:
      return "OK";
    case StreamHealth::kCorruptStream:
      return "CORRUPT_STREAM";
    case StreamHealth::kSilent:
      return "SILENT";
    case StreamHealth::kStalled:
      return "STALLED";
    case StreamHealth::kTransferErrors:
      return "TRANSFER_ERRORS";
    case StreamHealth::kNoDevice:
      return "NO_DEVICE";
  }
  return "UNKNOWN_STREAM_HEALTH";
}

UsbCamera::UsbCamera(const UsbCameraConfig& config, const hal::Clock& clock)
    : config_(config), clock_(clock), assembler_(nullptr) {
  if (config_.id_count == 0 || config_.id_count > UsbCameraConfig::kMaxIds ||
      config_.transfer_count < 1 || config_.transfer_count > kMaxTransfers ||
      config_.transfer_bytes < 16 * 1024 || config_.transfer_bytes % kBulkPacketBytes != 0 ||
      config_.command_timeout_ms <= 0) {
    init_status_ = UsbStatus::kBadArgument;
    return;
  }
  config_.serial[kSerialBytes] = '\0';
  // Sized once here; nothing of the driver's is allocated again.
  command_buffer_ = std::make_unique<std::uint8_t[]>(kMaxCommandBytes);
  reply_buffer_ = std::make_unique<std::uint8_t[]>(kReplyBufferBytes);
  transfer_memory_ = std::make_unique<std::uint8_t[]>(
      config_.transfer_bytes * static_cast<std::size_t>(config_.transfer_count));
  frame_ = std::make_unique<tof::RawFrame>();
  assembler_ = FrameAssembler(frame_.get());
  if (libusb_init(&ctx_) != 0) {
    ctx_ = nullptr;
    init_status_ = UsbStatus::kLibusbError;
    return;
  }
  for (int i = 0; i < config_.transfer_count; ++i) {
    transfers_[i] = libusb_alloc_transfer(0);
    if (transfers_[i] == nullptr) {
      init_status_ = UsbStatus::kNoMemory;
      return;
    }
  }
  if (libusb_has_capability(LIBUSB_CAP_HAS_HOTPLUG) != 0) {
    for (std::size_t i = 0; i < config_.id_count; ++i) {
      libusb_hotplug_callback_handle h = 0;
      if (libusb_hotplug_register_callback(
              ctx_,
              static_cast<libusb_hotplug_event>(LIBUSB_HOTPLUG_EVENT_DEVICE_ARRIVED |
                                                LIBUSB_HOTPLUG_EVENT_DEVICE_LEFT),
              static_cast<libusb_hotplug_flag>(0), config_.ids[i].vendor_id,
              config_.ids[i].product_id, LIBUSB_HOTPLUG_MATCH_ANY, &on_hotplug, this,
              &h) == LIBUSB_SUCCESS) {
        hotplug_handles_[hotplug_count_++] = h;
      }
    }
  }
  init_status_ = UsbStatus::kOk;
}

UsbCamera::~UsbCamera() {
  close();
  if (ctx_ != nullptr) {
    for (int i = 0; i < hotplug_count_; ++i)
      libusb_hotplug_deregister_callback(ctx_, hotplug_handles_[i]);
  }
  for (libusb_transfer* t : transfers_) {
    if (t != nullptr) libusb_free_transfer(t);
  }
  if (ctx_ != nullptr) libusb_exit(ctx_);
}

UsbStatus UsbCamera::map_error(int libusb_error) {
  switch (libusb_error) {
    case LIBUSB_SUCCESS:
      return UsbStatus::kOk;
    case LIBUSB_ERROR_TIMEOUT:
      return UsbStatus::kTimeout;
    case LIBUSB_ERROR_NO_DEVICE:
      gone_pending_ = true;
      return UsbStatus::kNoDevice;
    case LIBUSB_ERROR_PIPE:
      return UsbStatus::kStall;
    case LIBUSB_ERROR_ACCESS:
      return UsbStatus::kAccessDenied;
    case LIBUSB_ERROR_BUSY:
      return UsbStatus::kBusy;
    case LIBUSB_ERROR_NOT_FOUND:
      return UsbStatus::kNotFound;
    case LIBUSB_ERROR_NO_MEM:
      return UsbStatus::kNoMemory;
    default:
      return UsbStatus::kIoError;
  }
}

void UsbCamera::note_hotplug(libusb_device* device, bool left) {
  if (!left) {
    hotplug_arrived_ = true;
  } else if (device == device_.load()) {
    hotplug_left_ = true;
  }
}

UsbStatus UsbCamera::find_and_open() {
  libusb_device** list = nullptr;
  const ssize_t n = libusb_get_device_list(ctx_, &list);
  if (n < 0) return map_error(static_cast<int>(n));
  UsbStatus result = UsbStatus::kNotFound;
  for (ssize_t i = 0; i < n && handle_ == nullptr; ++i) {
    libusb_device_descriptor desc;
    if (libusb_get_device_descriptor(list[i], &desc) != 0) continue;
    bool listed = false;
    for (std::size_t k = 0; k < config_.id_count; ++k) {
      listed = listed || (desc.idVendor == config_.ids[k].vendor_id &&
                          desc.idProduct == config_.ids[k].product_id);
    }
    if (!listed) continue;
    libusb_device_handle* h = nullptr;
    const int r = libusb_open(list[i], &h);
    if (r != 0) {
      result = map_error(r);
      continue;
    }
    const int claimed = libusb_claim_interface(h, kInterfaceNumber);
    if (claimed != 0) {
      result = map_error(claimed);
      libusb_close(h);
      continue;
    }
    handle_ = h;
    Identity id;
    ReplyView reply;
    const UsbStatus s =
        command_locked(Command::kIdentify, nullptr, 0, &reply, config_.command_timeout_ms);
    const bool parsed =
        s == UsbStatus::kOk && parse_identity(reply.payload, reply.payload_bytes, &id);
    const bool serial_ok = config_.serial[0] == '\0' || std::strcmp(config_.serial, id.serial) == 0;
    if (!parsed || !serial_ok || id.protocol_version != kProtocolVersion) {
      result = s != UsbStatus::kOk
                   ? s
                   : (parsed && !serial_ok ? UsbStatus::kNotFound : UsbStatus::kBadReply);
      libusb_release_interface(h, kInterfaceNumber);
      libusb_close(h);
      handle_ = nullptr;
      continue;
    }
    identity_ = id;
    device_ = libusb_ref_device(list[i]);
    result = UsbStatus::kOk;
  }
  libusb_free_device_list(list, 1);
  return result;
}

void UsbCamera::close_handle() {
  if (handle_ != nullptr) {
    libusb_release_interface(handle_, kInterfaceNumber);
    libusb_close(handle_);
    handle_ = nullptr;
  }
  if (libusb_device* d = device_.exchange(nullptr)) libusb_unref_device(d);
}

UsbStatus UsbCamera::open() {
  if (init_status_ != UsbStatus::kOk) return init_status_;
  std::lock_guard<std::mutex> lock(command_mutex_);
  if (handle_ != nullptr) return UsbStatus::kOk;
  UsbStatus s = find_and_open();
  if (s == UsbStatus::kOk) s = apply_settings();
  if (s != UsbStatus::kOk) {
    close_handle();
    return s;
  }
  state_ = CameraState::kOpen;
  lost_reason_ = LostReason::kNone;
  quit_ = false;
  if (!event_thread_.joinable()) event_thread_ = std::thread([this] { event_loop(); });
  return UsbStatus::kOk;
}

void UsbCamera::close() {
  // Also when lost: a later open() must not find a capture still wanted.
  if (want_streaming_.load()) (void)stop_streaming();
  quit_ = true;
  if (event_thread_.joinable()) event_thread_.join();
  std::lock_guard<std::mutex> lock(command_mutex_);
  resubmit_ = false;
  cancel_all();
  wait_drained(1000000);
  close_handle();
  state_ = CameraState::kClosed;
  health_ = StreamHealth::kNotStreaming;
}

UsbStatus UsbCamera::apply_settings() {
  ReplyView reply;
  // A camera may still be streaming from before (a host that went away,
  // a camera given up as lost): it takes no use case then.
  UsbStatus s =
      command_locked(Command::kStopStream, nullptr, 0, &reply, config_.command_timeout_ms);
  if (s != UsbStatus::kOk) return s;
  const std::uint8_t use_case = config_.use_case_index;
  s = command_locked(Command::kSetUseCase, &use_case, 1, &reply, config_.command_timeout_ms);
  if (s != UsbStatus::kOk) return s;
  const std::uint8_t automatic = config_.exposure_automatic ? 1 : 0;
  s = command_locked(Command::kSetExposureMode, &automatic, 1, &reply, config_.command_timeout_ms);
  if (s != UsbStatus::kOk || config_.exposure_automatic || config_.exposure_us == 0) return s;
  std::uint8_t us[4];
  put_u32(us, config_.exposure_us);
  return command_locked(Command::kSetExposureTime, us, 4, &reply, config_.command_timeout_ms);
}

UsbStatus UsbCamera::command_locked(Command c, const std::uint8_t* payload,
                                    std::size_t payload_bytes, ReplyView* reply, int timeout_ms) {
  if (handle_ == nullptr) return UsbStatus::kNotOpen;
  auto fail = [&](UsbStatus s, std::uint64_t UsbCounters::*counter) {
    last_failed_command_ = c;
    std::lock_guard<std::mutex> lock(counters_mutex_);
    ++(counters_.*counter);
    return s;
  };
  {
    std::lock_guard<std::mutex> lock(counters_mutex_);
    ++counters_.commands;
  }
  const std::uint8_t tag = ++tag_;
  const std::size_t n =
      encode_command(c, tag, payload, payload_bytes, command_buffer_.get(), kMaxCommandBytes);
  if (n == 0) return fail(UsbStatus::kBadArgument, &UsbCounters::command_errors);
  int sent = 0;
  int r = libusb_bulk_transfer(handle_, kCommandEndpoint, command_buffer_.get(),
                               static_cast<int>(n), &sent, static_cast<unsigned>(timeout_ms));
  if (r != 0) {
    return fail(map_error(r), r == LIBUSB_ERROR_TIMEOUT ? &UsbCounters::command_timeouts
                                                        : &UsbCounters::command_errors);
  }
  for (int attempt = 0; attempt <= kMaxStaleReplies; ++attempt) {
    int got = 0;
    r = libusb_bulk_transfer(handle_, kReplyEndpoint, reply_buffer_.get(),
                             static_cast<int>(kReplyBufferBytes), &got,
                             static_cast<unsigned>(timeout_ms));
    if (r != 0) {
      return fail(map_error(r), r == LIBUSB_ERROR_TIMEOUT ? &UsbCounters::command_timeouts
                                                          : &UsbCounters::command_errors);
    }
    const ParseStatus p =
        parse_reply(reply_buffer_.get(), static_cast<std::size_t>(got), c, tag, reply);
    if (p == ParseStatus::kWrongTag || p == ParseStatus::kWrongCommand) {
      // The reply to an earlier command that timed out: not ours.
      std::lock_guard<std::mutex> lock(counters_mutex_);
      ++counters_.stale_replies;
      continue;
    }
    if (p != ParseStatus::kOk) {
      last_parse_ = p;
      return fail(UsbStatus::kBadReply, &UsbCounters::command_errors);
    }
    if (reply->status != ReplyStatus::kOk) {
      last_refusal_ = reply->status;
      return fail(UsbStatus::kRefused, &UsbCounters::command_refusals);
    }
    return UsbStatus::kOk;
  }
  last_parse_ = ParseStatus::kWrongTag;
  return fail(UsbStatus::kBadReply, &UsbCounters::command_errors);
}

UsbStatus UsbCamera::identify(Identity* out) {
  ReplyView reply;
  std::lock_guard<std::mutex> lock(command_mutex_);
  const UsbStatus s =
      command_locked(Command::kIdentify, nullptr, 0, &reply, config_.command_timeout_ms);
  if (s != UsbStatus::kOk) return s;
  if (!parse_identity(reply.payload, reply.payload_bytes, out)) {
    last_parse_ = ParseStatus::kBadLength;
    return UsbStatus::kBadReply;
  }
  return UsbStatus::kOk;
}

UsbStatus UsbCamera::read_calibration(std::uint8_t* out, std::size_t capacity, std::size_t* bytes) {
  std::lock_guard<std::mutex> lock(command_mutex_);
  ReplyView reply;
  UsbStatus s =
      command_locked(Command::kCalibrationInfo, nullptr, 0, &reply, config_.command_timeout_ms);
  if (s != UsbStatus::kOk) return s;
  if (reply.payload_bytes != 8) {
    last_parse_ = ParseStatus::kBadLength;
    return UsbStatus::kBadReply;
  }
  const std::uint32_t size = get_u32(reply.payload);
  const std::uint32_t crc = get_u32(reply.payload + 4);
  if (size > capacity) return UsbStatus::kBadArgument;
  std::size_t done = 0;
  while (done < size) {
    const std::size_t chunk =
        size - done < kMaxReplyPayloadBytes ? size - done : kMaxReplyPayloadBytes;
    std::uint8_t request[6];
    put_u32(request, static_cast<std::uint32_t>(done));
    put_u16(request + 4, static_cast<std::uint16_t>(chunk));
    s = command_locked(Command::kReadCalibration, request, 6, &reply, config_.command_timeout_ms);
    if (s != UsbStatus::kOk) return s;
    if (reply.payload_bytes != chunk) {
      last_parse_ = ParseStatus::kBadLength;
      return UsbStatus::kBadReply;
    }
    std::memcpy(out + done, reply.payload, chunk);
    done += chunk;
  }
  if (crc32(out, size) != crc) {
    last_parse_ = ParseStatus::kBadCrc;
    return UsbStatus::kBadReply;
  }
  *bytes = size;
  return UsbStatus::kOk;
}

UsbStatus UsbCamera::set_use_case(std::uint8_t use_case_index) {
  std::lock_guard<std::mutex> lock(command_mutex_);
  if (want_streaming_) return UsbStatus::kStreaming;
  ReplyView reply;
  const UsbStatus s =
      command_locked(Command::kSetUseCase, &use_case_index, 1, &reply, config_.command_timeout_ms);
  if (s == UsbStatus::kOk) config_.use_case_index = use_case_index;
  return s;
}

UsbStatus UsbCamera::set_exposure_mode(bool automatic) {
  std::lock_guard<std::mutex> lock(command_mutex_);
  ReplyView reply;
  const std::uint8_t mode = automatic ? 1 : 0;
  const UsbStatus s =
      command_locked(Command::kSetExposureMode, &mode, 1, &reply, config_.command_timeout_ms);
  if (s == UsbStatus::kOk) config_.exposure_automatic = automatic;
  return s;
}

UsbStatus UsbCamera::set_exposure_time(std::uint32_t exposure_us) {
  std::lock_guard<std::mutex> lock(command_mutex_);
  ReplyView reply;
  std::uint8_t us[4];
  put_u32(us, exposure_us);
  const UsbStatus s =
      command_locked(Command::kSetExposureTime, us, 4, &reply, config_.command_timeout_ms);
  if (s == UsbStatus::kOk) config_.exposure_us = exposure_us;
  return s;
}

UsbCounters UsbCamera::counters() const {
  std::lock_guard<std::mutex> lock(counters_mutex_);
  return counters_;
}

}  // namespace pico_flexx
