// The Pico Flexx USB driver's stream: the pool of bulk transfers, frame
// reassembly and delivery, and the event thread that watches for an
// unplugged, stalled, silent or corrupt stream and brings the camera back.
#include <libusb.h>

#include <sys/time.h>

#include "hal/use_case.hpp"
#include "pico_flexx/usb_camera.hpp"

namespace pico_flexx {
namespace {

// How long libusb waits for events per round of the event thread; the
// supervision runs between rounds.
constexpr long kEventRoundUs = 10000;
// In-flight transfers are cancelled and must come back within this.
constexpr std::int64_t kDrainTimeoutUs = 1000000;
// Silence is at least this many frame periods of the use case.
constexpr std::int64_t kSilentPeriods = 4;

std::int64_t ms_to_us(int ms) {
  return static_cast<std::int64_t>(ms) * 1000;
}

// The health the ladder reports while it climbs for `cause`.
StreamHealth ladder_health(LostReason cause) {
  switch (cause) {
    case LostReason::kStalled:
      return StreamHealth::kStalled;
    case LostReason::kTransferErrors:
      return StreamHealth::kTransferErrors;
    case LostReason::kNone:
    case LostReason::kUnplugged:
    case LostReason::kSilent:
    case LostReason::kReinitFailed:
      break;
  }
  return StreamHealth::kSilent;
}

}  // namespace

UsbStatus UsbCamera::submit_all() {
  for (int i = 0; i < config_.transfer_count; ++i) {
    libusb_transfer* t = transfers_[i];
    libusb_fill_bulk_transfer(
        t, handle_, kStreamEndpoint,
        transfer_memory_.get() + static_cast<std::size_t>(i) * config_.transfer_bytes,
        static_cast<int>(config_.transfer_bytes), &UsbCamera::stream_callback, this, 0);
    ++in_flight_;
    const int r = libusb_submit_transfer(t);
    if (r != 0) {
      --in_flight_;
      return map_error(r);
    }
    std::lock_guard<std::mutex> lock(counters_mutex_);
    ++counters_.transfers_submitted;
  }
  return UsbStatus::kOk;
}

void UsbCamera::cancel_all() {
  for (int i = 0; i < config_.transfer_count; ++i) {
    if (transfers_[i] != nullptr) libusb_cancel_transfer(transfers_[i]);
  }
}

bool UsbCamera::wait_drained(std::int64_t timeout_us) {
  // Bounded by the deadline: one round of events per pass.
  const std::int64_t deadline_us = clock_.now_us() + timeout_us;
  while (in_flight_.load() > 0 && clock_.now_us() < deadline_us) {
    timeval tv{0, kEventRoundUs};
    libusb_handle_events_timeout_completed(ctx_, &tv, nullptr);
  }
  return in_flight_.load() == 0;
}

void UsbCamera::stream_callback(libusb_transfer* transfer) {
  static_cast<UsbCamera*>(transfer->user_data)->on_stream_transfer(transfer);
}

void UsbCamera::on_stream_transfer(libusb_transfer* t) {
  --in_flight_;
  const std::int64_t now_us = clock_.now_us();
  switch (t->status) {
    case LIBUSB_TRANSFER_COMPLETED:
      note_stream_completion(t, now_us);
      break;
    case LIBUSB_TRANSFER_CANCELLED: {
      std::lock_guard<std::mutex> lock(counters_mutex_);
      ++counters_.transfers_cancelled;
      return;
    }
    case LIBUSB_TRANSFER_STALL: {
      stalled_pending_ = true;
      std::lock_guard<std::mutex> lock(counters_mutex_);
      ++counters_.stalls;
      ++counters_.transfers_failed;
      return;
    }
    case LIBUSB_TRANSFER_NO_DEVICE: {
      gone_pending_ = true;
      std::lock_guard<std::mutex> lock(counters_mutex_);
      ++counters_.transfers_failed;
      return;
    }
    default: {
      failed_pending_ = true;
      std::lock_guard<std::mutex> lock(counters_mutex_);
      ++counters_.transfers_failed;
      return;
    }
  }
  if (!resubmit_) return;
  ++in_flight_;
  const int r = libusb_submit_transfer(t);
  if (r != 0) {
    --in_flight_;
    (void)map_error(r);  // notes a vanished device
    failed_pending_ = true;
    return;
  }
  std::lock_guard<std::mutex> lock(counters_mutex_);
  ++counters_.transfers_submitted;
}

void UsbCamera::note_stream_completion(const libusb_transfer* t, std::int64_t now_us) {
  // Bytes of any kind say the camera is alive, good frames or not.
  if (t->actual_length > 0) {
    last_bytes_us_ = now_us;
    bytes_seen_ = true;
  }
  const AssemblyEvent e = assembler_.on_transfer(
      t->buffer, static_cast<std::size_t>(t->actual_length), static_cast<std::size_t>(t->length));
  // A frame's first transfer carries its header: the least delay from the
  // camera's capture to it is one transfer's time, where the last
  // transfer's adds the whole frame's (17 ms for MODE_9 at USB 2.0).
  if (assembler_.started_frame()) frame_first_transfer_us_ = now_us;
  if (e == AssemblyEvent::kFrameReady) {
    const FrameHeader& h = assembler_.last_header();
    const std::int64_t camera_us = static_cast<std::int64_t>(h.capture_time_us);
    frame_->capture_time_us = clock_map_.to_host_us(camera_us, frame_first_transfer_us_);
    if (listener_ != nullptr) {
      RawFrameInfo info;
      info.sequence = h.sequence;
      info.use_case_index = h.use_case_index;
      info.first_transfer_us = frame_first_transfer_us_;
      info.last_transfer_us = now_us;
      info.camera_time_us = camera_us;
      info.capture_time_us = frame_->capture_time_us;
      info.clock_window_change_us = clock_map_.window_change_us();
      listener_->on_raw_frame(info, *frame_);
    }
    last_frame_us_ = now_us;
    consecutive_bad_frames_ = 0;
    rung_ = 0;
  } else if (e == AssemblyEvent::kDropped) {
    ++consecutive_bad_frames_;
  }
  std::lock_guard<std::mutex> lock(counters_mutex_);
  ++counters_.transfers_completed;
  counters_.bytes_received += static_cast<std::uint64_t>(t->actual_length);
  counters_.assembly = assembler_.counts();
  counters_.consecutive_bad_frames = consecutive_bad_frames_;
  if (e == AssemblyEvent::kFrameReady) {
    ++counters_.frames_delivered;
    counters_.last_delivery_us = clock_.now_us() - now_us;
  }
}

UsbStatus UsbCamera::reacquire_for_start() {
  // The camera was lost or unplugged and the capture stopped: find it now
  // rather than wait for the event thread's next search.
  if (!stop_transfers()) return UsbStatus::kIoError;
  close_handle();
  const UsbStatus s = reopen_camera();
  if (s != UsbStatus::kOk) return s == UsbStatus::kNotFound ? UsbStatus::kNoDevice : s;
  std::lock_guard<std::mutex> lock(counters_mutex_);
  ++counters_.reacquisitions;
  return UsbStatus::kOk;
}

UsbStatus UsbCamera::start_streaming(RawFrameListener* listener) {
  std::lock_guard<std::mutex> lock(command_mutex_);
  if (state_.load() == CameraState::kClosed) return UsbStatus::kNotOpen;
  if (want_streaming_) return UsbStatus::kStreaming;
  const CameraState state = state_.load();
  if (state == CameraState::kLost || state == CameraState::kWaitingForDevice) {
    const UsbStatus s = reacquire_for_start();
    if (s != UsbStatus::kOk) return s;
    lost_reason_ = LostReason::kNone;
    state_ = CameraState::kOpen;
  }
  if (handle_ == nullptr) return UsbStatus::kNotOpen;
  listener_ = listener;
  assembler_.restart();
  clock_map_.reset();
  ReplyView reply;
  UsbStatus s =
      command_locked(Command::kStartStream, nullptr, 0, &reply, config_.command_timeout_ms);
  if (s != UsbStatus::kOk) return s;
  want_streaming_ = true;
  s = resume_stream(clock_.now_us());
  state_ = CameraState::kStreaming;
  return s;
}

UsbStatus UsbCamera::stop_streaming() {
  std::lock_guard<std::mutex> lock(command_mutex_);
  if (!want_streaming_) return UsbStatus::kNotStreaming;
  want_streaming_ = false;
  (void)stop_transfers();
  const CameraState was = state_.load();
  // Lost or unplugged: nothing to tell the camera. The search goes on, and
  // a camera found again is left open, not streaming.
  if (was == CameraState::kLost || was == CameraState::kWaitingForDevice) return UsbStatus::kOk;
  state_ = CameraState::kOpen;
  health_ = StreamHealth::kNotStreaming;
  ReplyView reply;
  return command_locked(Command::kStopStream, nullptr, 0, &reply, config_.command_timeout_ms);
}

void UsbCamera::event_loop() {
  // Bounded per round: one wait for events, then one step of supervision.
  while (!quit_.load()) {
    timeval tv{0, kEventRoundUs};
    libusb_handle_events_timeout_completed(ctx_, &tv, nullptr);
    // A command in progress owns the handle; supervision waits a round.
    if (command_mutex_.try_lock()) {
      supervise(clock_.now_us());
      command_mutex_.unlock();
    }
  }
}

void UsbCamera::supervise(std::int64_t now_us) {
  switch (state_.load()) {
    case CameraState::kClosed:
      return;
    case CameraState::kWaitingForDevice:
      try_reconnect(now_us);
      return;
    case CameraState::kLost:
      supervise_lost(now_us);
      return;
    case CameraState::kOpen:
    case CameraState::kStreaming:
    case CameraState::kRecovering:
      supervise_stream(now_us);
      return;
  }
}

void UsbCamera::supervise_stream(std::int64_t now_us) {
  if (gone_pending_.exchange(false) || hotplug_left_.exchange(false)) {
    handle_unplug(now_us);
    return;
  }
  hotplug_arrived_ = false;  // another camera; not ours while this one works
  if (!want_streaming_) return;
  if (stalled_pending_.exchange(false)) {
    climb_ladder(now_us, LostReason::kStalled);
    return;
  }
  if (failed_pending_.exchange(false)) {
    climb_ladder(now_us, LostReason::kTransferErrors);
    return;
  }
  check_stream_liveness(now_us);
}

std::int64_t UsbCamera::silence_window_us() const {
  std::size_t count = 0;
  const std::int64_t period_us =
      hal::frame_period_us(hal::use_cases(&count)[config_.use_case_index]);
  const std::int64_t silence_us = ms_to_us(config_.silence_ms);
  return silence_us > kSilentPeriods * period_us ? silence_us : kSilentPeriods * period_us;
}

void UsbCamera::check_stream_liveness(std::int64_t now_us) {
  const std::int64_t window_us = silence_window_us();
  if (now_us - last_bytes_us_.load() > window_us) {
    // Nothing at all from the camera: the ladder may bring it back.
    {
      std::lock_guard<std::mutex> lock(counters_mutex_);
      ++counters_.silences;
    }
    climb_ladder(now_us, LostReason::kSilent);
    return;
  }
  if (now_us - last_frame_us_.load() > window_us) {
    // Bytes, but no frame passes: the camera is there and streaming, so
    // resetting it would only add silence. Reported, and left alone.
    report_corrupt_stream();
    return;
  }
  // After a rung or a restart, the ladder's reason stands until bytes come.
  if (bytes_seen_.load()) health_ = StreamHealth::kOk;
}

void UsbCamera::report_corrupt_stream() {
  if (health_.exchange(StreamHealth::kCorruptStream) == StreamHealth::kCorruptStream) return;
  std::lock_guard<std::mutex> lock(counters_mutex_);
  ++counters_.corrupt_streams;
}

bool UsbCamera::stop_transfers() {
  resubmit_ = false;
  cancel_all();
  return wait_drained(kDrainTimeoutUs);
}

void UsbCamera::climb_ladder(std::int64_t now_us, LostReason cause) {
  state_ = CameraState::kRecovering;
  health_ = ladder_health(cause);
  (void)stop_transfers();
  if (gone_pending_.load()) return;  // unplugged meanwhile: the next round handles it
  // The reason the camera is lost if the ladder runs out: what sent it up
  // the first rung, unless a rung itself failed on the way.
  if (rung_ == 0) ladder_reason_ = cause;
  ++rung_;
  UsbStatus s = UsbStatus::kOk;
  ReplyView reply;
  switch (rung_) {
    case 1: {
      s = map_error(libusb_clear_halt(handle_, kStreamEndpoint));
      std::lock_guard<std::mutex> lock(counters_mutex_);
      ++counters_.clear_halts;
      break;
    }
    case 2: {
      {
        std::lock_guard<std::mutex> lock(counters_mutex_);
        ++counters_.reinitialisations;
      }
      (void)command_locked(Command::kStopStream, nullptr, 0, &reply, config_.command_timeout_ms);
      s = map_error(libusb_clear_halt(handle_, kStreamEndpoint));
      if (s == UsbStatus::kOk) s = apply_settings();
      if (s == UsbStatus::kOk)
        s = command_locked(Command::kStartStream, nullptr, 0, &reply, config_.command_timeout_ms);
      break;
    }
    case 3: {
      {
        std::lock_guard<std::mutex> lock(counters_mutex_);
        ++counters_.usb_resets;
      }
      const int r = libusb_reset_device(handle_);
      if (r == LIBUSB_ERROR_NOT_FOUND || r == LIBUSB_ERROR_NO_DEVICE) {
        // It came back as another device: find it as after an unplug.
        handle_unplug(now_us);
        return;
      }
      s = map_error(r);
      assembler_.restart();  // the camera restarted its sequence
      clock_map_.reset();    // and its clock
      if (s == UsbStatus::kOk) s = apply_settings();
      if (s == UsbStatus::kOk)
        s = command_locked(Command::kStartStream, nullptr, 0, &reply, config_.command_timeout_ms);
      break;
    }
    default:
      become_lost(ladder_reason_, now_us);
      return;
  }
  // The partial frame in progress is gone with the cancelled transfers.
  assembler_.abandon_frame();
  last_frame_us_ = now_us;
  last_bytes_us_ = now_us;
  bytes_seen_ = false;
  if (s != UsbStatus::kOk) {
    ladder_reason_ = LostReason::kReinitFailed;
    failed_pending_ = true;  // the next round climbs on
    return;
  }
  resubmit_ = true;
  if (submit_all() != UsbStatus::kOk) failed_pending_ = true;
  state_ = CameraState::kStreaming;
}

void UsbCamera::become_lost(LostReason reason, std::int64_t now_us) {
  (void)stop_transfers();
  lost_reason_ = reason;
  // The search goes on, backing off from the reconnect poll.
  reacquire_interval_us_ = ms_to_us(config_.reconnect_poll_ms);
  next_reacquire_us_ = now_us + reacquire_interval_us_;
  state_ = CameraState::kLost;
}

void UsbCamera::handle_unplug(std::int64_t now_us) {
  {
    std::lock_guard<std::mutex> lock(counters_mutex_);
    ++counters_.unplugs;
  }
  state_ = CameraState::kWaitingForDevice;
  health_ = StreamHealth::kNoDevice;
  (void)stop_transfers();
  close_handle();
  gone_pending_ = false;
  hotplug_left_ = false;
  unplugged_since_us_ = now_us;
  next_search_us_ = now_us + ms_to_us(config_.reconnect_poll_ms);
}

UsbStatus UsbCamera::reopen_camera() {
  UsbStatus s = find_and_open();
  if (s == UsbStatus::kOk) s = apply_settings();
  ReplyView reply;
  if (s == UsbStatus::kOk && want_streaming_) {
    s = command_locked(Command::kStartStream, nullptr, 0, &reply, config_.command_timeout_ms);
  }
  if (s != UsbStatus::kOk) close_handle();
  return s;
}

UsbStatus UsbCamera::resume_stream(std::int64_t now_us) {
  gone_pending_ = false;
  stalled_pending_ = failed_pending_ = false;
  assembler_.restart();  // a camera powered up or restarted counts from 0
  clock_map_.reset();    // its clock too
  rung_ = 0;
  consecutive_bad_frames_ = 0;
  last_frame_us_ = now_us;
  last_bytes_us_ = now_us;
  bytes_seen_ = false;
  {
    std::lock_guard<std::mutex> lock(counters_mutex_);
    counters_.consecutive_bad_frames = 0;
  }
  health_ = want_streaming_ ? StreamHealth::kOk : StreamHealth::kNotStreaming;
  if (!want_streaming_) return UsbStatus::kOk;
  resubmit_ = true;
  const UsbStatus s = submit_all();
  if (s != UsbStatus::kOk) failed_pending_ = true;  // the ladder takes it from there
  return s;
}

void UsbCamera::try_reconnect(std::int64_t now_us) {
  if (now_us - unplugged_since_us_ > ms_to_us(config_.reconnect_window_ms)) {
    become_lost(LostReason::kUnplugged, now_us);
    return;
  }
  if (!hotplug_arrived_.exchange(false) && now_us < next_search_us_) return;
  next_search_us_ = now_us + ms_to_us(config_.reconnect_poll_ms);
  if (reopen_camera() != UsbStatus::kOk) return;
  {
    std::lock_guard<std::mutex> lock(counters_mutex_);
    ++counters_.replugs;
  }
  (void)resume_stream(now_us);
  state_ = want_streaming_ ? CameraState::kStreaming : CameraState::kOpen;
}

void UsbCamera::supervise_lost(std::int64_t now_us) {
  if (gone_pending_.exchange(false) || hotplug_left_.exchange(false)) {
    // Gone while lost: nothing to probe until it is found again.
    (void)stop_transfers();
    close_handle();
    health_ = StreamHealth::kNoDevice;
  }
  // A search that restarted the stream succeeds when bytes arrive: a
  // streaming camera is not lost, whatever its frames look like.
  if (want_streaming_ && resubmit_ && bytes_seen_.load()) {
    finish_reacquisition(now_us);
    return;
  }
  if (!hotplug_arrived_.exchange(false) && now_us < next_reacquire_us_) return;
  attempt_reacquisition(now_us);
}

void UsbCamera::attempt_reacquisition(std::int64_t now_us) {
  {
    std::lock_guard<std::mutex> lock(counters_mutex_);
    ++counters_.reacquire_attempts;
  }
  next_reacquire_us_ = now_us + reacquire_interval_us_;
  const std::int64_t max_interval_us = ms_to_us(config_.reacquire_max_interval_ms);
  reacquire_interval_us_ =
      2 * reacquire_interval_us_ < max_interval_us ? 2 * reacquire_interval_us_ : max_interval_us;
  // Start afresh: the old handle may be stale (a replug) or its camera hung.
  if (!stop_transfers()) return;  // transfers still out: try again later
  close_handle();
  if (reopen_camera() != UsbStatus::kOk) {
    health_ = StreamHealth::kNoDevice;
    return;
  }
  (void)resume_stream(now_us);  // a failed submission: the next search retries
  if (!want_streaming_) finish_reacquisition(now_us);
}

void UsbCamera::finish_reacquisition(std::int64_t now_us) {
  {
    std::lock_guard<std::mutex> lock(counters_mutex_);
    ++counters_.reacquisitions;
  }
  lost_reason_ = LostReason::kNone;
  last_frame_us_ = now_us;
  last_bytes_us_ = now_us;
  state_ = want_streaming_ ? CameraState::kStreaming : CameraState::kOpen;
}

}  // namespace pico_flexx
