// The Pico Flexx USB driver's stream: the pool of bulk transfers, frame
// reassembly and delivery, and the event thread that watches for an
// unplugged, stalled or silent camera and brings it back.
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
    case LIBUSB_TRANSFER_COMPLETED: {
      const AssemblyEvent e =
          assembler_.on_transfer(t->buffer, static_cast<std::size_t>(t->actual_length),
                                 static_cast<std::size_t>(t->length));
      if (e == AssemblyEvent::kFrameReady && listener_ != nullptr) {
        RawFrameInfo info;
        info.sequence = assembler_.last_header().sequence;
        info.use_case_index = assembler_.last_header().use_case_index;
        info.last_transfer_us = now_us;
        frame_->capture_time_us = now_us;
        listener_->on_raw_frame(info, *frame_);
        last_frame_us_ = now_us;
        rung_ = 0;
      }
      std::lock_guard<std::mutex> lock(counters_mutex_);
      ++counters_.transfers_completed;
      counters_.bytes_received += static_cast<std::uint64_t>(t->actual_length);
      counters_.assembly = assembler_.counts();
      if (e == AssemblyEvent::kFrameReady) {
        ++counters_.frames_delivered;
        counters_.last_delivery_us = clock_.now_us() - now_us;
      }
      break;
    }
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

UsbStatus UsbCamera::start_streaming(RawFrameListener* listener) {
  std::lock_guard<std::mutex> lock(command_mutex_);
  if (handle_ == nullptr) return UsbStatus::kNotOpen;
  if (want_streaming_) return UsbStatus::kStreaming;
  listener_ = listener;
  assembler_.restart();
  ReplyView reply;
  UsbStatus s =
      command_locked(Command::kStartStream, nullptr, 0, &reply, config_.command_timeout_ms);
  if (s != UsbStatus::kOk) return s;
  rung_ = 0;
  last_frame_us_ = clock_.now_us();
  stalled_pending_ = failed_pending_ = false;
  resubmit_ = true;
  want_streaming_ = true;
  s = submit_all();
  state_ = CameraState::kStreaming;
  return s;
}

UsbStatus UsbCamera::stop_streaming() {
  std::lock_guard<std::mutex> lock(command_mutex_);
  if (!want_streaming_) return UsbStatus::kNotStreaming;
  want_streaming_ = false;
  resubmit_ = false;
  cancel_all();
  wait_drained(kDrainTimeoutUs);
  const CameraState was = state_.load();
  if (was == CameraState::kLost || was == CameraState::kWaitingForDevice) return UsbStatus::kOk;
  state_ = CameraState::kOpen;
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
  const CameraState state = state_.load();
  if (state == CameraState::kClosed || state == CameraState::kLost) return;
  if (state == CameraState::kWaitingForDevice) {
    try_reconnect(now_us);
    return;
  }
  if (gone_pending_.exchange(false) || hotplug_left_.exchange(false)) {
    handle_unplug(now_us);
    return;
  }
  hotplug_arrived_ = false;  // another camera; not ours while this one works
  if (!want_streaming_) return;
  const bool stalled = stalled_pending_.exchange(false);
  const bool failed = failed_pending_.exchange(false);
  if (stalled || failed) {
    climb_ladder(now_us, stalled);
    return;
  }
  std::size_t count = 0;
  const std::int64_t period_us =
      hal::frame_period_us(hal::use_cases(&count)[config_.use_case_index]);
  std::int64_t silence_us = static_cast<std::int64_t>(config_.silence_ms) * 1000;
  if (silence_us < kSilentPeriods * period_us) silence_us = kSilentPeriods * period_us;
  if (now_us - last_frame_us_ > silence_us) {
    {
      std::lock_guard<std::mutex> lock(counters_mutex_);
      ++counters_.silences;
    }
    climb_ladder(now_us, false);
  }
}

void UsbCamera::climb_ladder(std::int64_t now_us, bool stalled) {
  state_ = CameraState::kRecovering;
  resubmit_ = false;
  cancel_all();
  wait_drained(kDrainTimeoutUs);
  if (gone_pending_.load()) return;  // unplugged meanwhile: the next round handles it
  // The reason the camera is lost if the ladder runs out: what sent it up
  // the first rung, unless a rung itself failed on the way.
  if (rung_ == 0) ladder_reason_ = stalled ? LostReason::kStalled : LostReason::kSilent;
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
      if (s == UsbStatus::kOk) s = apply_settings();
      if (s == UsbStatus::kOk)
        s = command_locked(Command::kStartStream, nullptr, 0, &reply, config_.command_timeout_ms);
      break;
    }
    default:
      become_lost(ladder_reason_);
      return;
  }
  // The partial frame in progress is gone with the cancelled transfers.
  assembler_.abandon_frame();
  last_frame_us_ = now_us;
  if (s != UsbStatus::kOk) {
    ladder_reason_ = LostReason::kReinitFailed;
    failed_pending_ = true;  // the next round climbs on
    return;
  }
  resubmit_ = true;
  if (submit_all() != UsbStatus::kOk) failed_pending_ = true;
  state_ = CameraState::kStreaming;
}

void UsbCamera::become_lost(LostReason reason) {
  resubmit_ = false;
  cancel_all();
  wait_drained(kDrainTimeoutUs);
  lost_reason_ = reason;
  state_ = CameraState::kLost;
}

void UsbCamera::handle_unplug(std::int64_t now_us) {
  {
    std::lock_guard<std::mutex> lock(counters_mutex_);
    ++counters_.unplugs;
  }
  state_ = CameraState::kWaitingForDevice;
  resubmit_ = false;
  cancel_all();
  wait_drained(kDrainTimeoutUs);
  close_handle();
  gone_pending_ = false;
  hotplug_left_ = false;
  unplugged_since_us_ = now_us;
  next_search_us_ = now_us + static_cast<std::int64_t>(config_.reconnect_poll_ms) * 1000;
}

void UsbCamera::try_reconnect(std::int64_t now_us) {
  if (now_us - unplugged_since_us_ >
      static_cast<std::int64_t>(config_.reconnect_window_ms) * 1000) {
    lost_reason_ = LostReason::kUnplugged;
    state_ = CameraState::kLost;
    return;
  }
  if (!hotplug_arrived_.exchange(false) && now_us < next_search_us_) return;
  next_search_us_ = now_us + static_cast<std::int64_t>(config_.reconnect_poll_ms) * 1000;
  if (find_and_open() != UsbStatus::kOk) return;
  ReplyView reply;
  UsbStatus s = apply_settings();
  if (s == UsbStatus::kOk && want_streaming_) {
    s = command_locked(Command::kStartStream, nullptr, 0, &reply, config_.command_timeout_ms);
  }
  if (s != UsbStatus::kOk) {
    close_handle();
    return;
  }
  {
    std::lock_guard<std::mutex> lock(counters_mutex_);
    ++counters_.replugs;
  }
  gone_pending_ = false;
  stalled_pending_ = failed_pending_ = false;
  assembler_.restart();  // a camera powered up afresh counts from 0
  rung_ = 0;
  if (!want_streaming_) {
    state_ = CameraState::kOpen;
    return;
  }
  last_frame_us_ = now_us;
  resubmit_ = true;
  state_ = CameraState::kStreaming;
  if (submit_all() != UsbStatus::kOk) failed_pending_ = true;
}

}  // namespace pico_flexx
