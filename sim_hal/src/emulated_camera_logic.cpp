// The emulated Pico Flexx's camera side: the project's protocol's
// commands, and raw frames made at the use case's rate and cut into the
// host's stream transfers. Called from the USB side with the mutex held.
#include <cerrno>
#include <cstring>

#include "emulated_pico_flexx_impl.hpp"

namespace sim_hal {

using pico_flexx::Command;
using pico_flexx::ReplyStatus;

namespace {
// Frames the camera holds when the host falls behind: a second at 45 fps.
// Deep on purpose. A real camera's frames go into transfers the host
// queued in the kernel, with no host thread running; here every transfer
// is filled only when umockdev's thread and the host's get the CPU, which
// on a loaded two-core machine can take a few hundred milliseconds.
constexpr std::uint64_t kFifoFrames = 45;
}  // namespace

void EmulatedPicoFlexx::Impl::power_up() {
  power_up_us = clock->now_us();
  capture_log = {};
  captures_logged = 0;
  streaming = false;
  exposure_automatic = false;
  exposure_us = config.exposure_us;
  use_case_index = config.use_case_index;
  sequence = 0;
  stream_halted = false;
  halt_persistent = false;
  replies.clear();
  frame_active = false;
  zero_length_pending = false;
}

void EmulatedPicoFlexx::Impl::queue_reply(Command command, std::uint8_t tag, ReplyStatus status,
                                          const std::uint8_t* payload, std::size_t payload_bytes) {
  PendingReply reply;
  reply.bytes.resize(pico_flexx::kMaxReplyBytes);
  reply.bytes.resize(pico_flexx::encode_reply(command, tag, status, payload, payload_bytes,
                                              reply.bytes.data(), reply.bytes.size()));
  reply.ready_us = clock->now_us() + reply_delay_us;
  replies.push_back(std::move(reply));
}

void EmulatedPicoFlexx::Impl::execute_command(const std::uint8_t* data, std::size_t length) {
  ++counts.commands;
  pico_flexx::CommandView cmd;
  const pico_flexx::ParseStatus parsed = pico_flexx::parse_command(data, length, &cmd);
  if (parsed != pico_flexx::ParseStatus::kOk) {
    // A damaged command is answered when its header can be read, so the
    // host learns at once instead of waiting for a timeout.
    if (length >= pico_flexx::kPacketHeaderBytes && data[0] == 'P' && data[1] == 'C') {
      queue_reply(static_cast<Command>(data[2]), data[3],
                  parsed == pico_flexx::ParseStatus::kBadCrc ? ReplyStatus::kBadCrc
                                                             : ReplyStatus::kBadLength,
                  nullptr, 0);
    }
    return;
  }
  if (muted_commands > 0) {
    --muted_commands;
    ++counts.commands_muted;
    return;
  }
  std::size_t use_case_count = 0;
  const hal::UseCase* use_cases = hal::use_cases(&use_case_count);
  const std::uint8_t* p = cmd.payload;
  const std::size_t n = cmd.payload_bytes;
  auto reply = [&](ReplyStatus status, const std::uint8_t* payload = nullptr,
                   std::size_t bytes = 0) {
    queue_reply(cmd.command, cmd.tag, status, payload, bytes);
  };
  switch (cmd.command) {
    case Command::kIdentify: {
      if (n != 0) return reply(ReplyStatus::kBadLength);
      pico_flexx::Identity id;
      id.vendor_id = pico_flexx::kVendorId;
      id.product_id = pico_flexx::kProductId;
      id.protocol_version = pico_flexx::kProtocolVersion;
      id.firmware_major = config.firmware_major;
      id.firmware_minor = config.firmware_minor;
      std::strncpy(id.serial, config.serial.c_str(), pico_flexx::kSerialBytes);
      std::uint8_t out[pico_flexx::kIdentityBytes];
      pico_flexx::encode_identity(id, out);
      return reply(ReplyStatus::kOk, out, sizeof out);
    }
    case Command::kCalibrationInfo: {
      if (n != 0) return reply(ReplyStatus::kBadLength);
      std::uint8_t out[8];
      const auto* bytes = reinterpret_cast<const std::uint8_t*>(config.calibration.data());
      pico_flexx::put_u32(out, static_cast<std::uint32_t>(config.calibration.size()));
      pico_flexx::put_u32(out + 4, pico_flexx::crc32(bytes, config.calibration.size()));
      return reply(ReplyStatus::kOk, out, sizeof out);
    }
    case Command::kReadCalibration: {
      if (n != 6) return reply(ReplyStatus::kBadLength);
      const std::uint32_t offset = pico_flexx::get_u32(p);
      const std::uint16_t bytes = pico_flexx::get_u16(p + 4);
      if (bytes == 0 || bytes > pico_flexx::kMaxReplyPayloadBytes ||
          offset > config.calibration.size() || bytes > config.calibration.size() - offset) {
        return reply(ReplyStatus::kOutOfRange);
      }
      return reply(ReplyStatus::kOk,
                   reinterpret_cast<const std::uint8_t*>(config.calibration.data()) + offset,
                   bytes);
    }
    case Command::kSetUseCase: {
      if (n != 1) return reply(ReplyStatus::kBadLength);
      if (p[0] >= use_case_count) return reply(ReplyStatus::kOutOfRange);
      if (streaming) return reply(ReplyStatus::kBusy);
      use_case_index = p[0];
      if (exposure_us > use_cases[use_case_index].max_exposure_us) {
        exposure_us = use_cases[use_case_index].max_exposure_us;
      }
      return reply(ReplyStatus::kOk);
    }
    case Command::kSetExposureMode: {
      if (n != 1) return reply(ReplyStatus::kBadLength);
      if (p[0] > 1) return reply(ReplyStatus::kOutOfRange);
      exposure_automatic = p[0] == 1;
      return reply(ReplyStatus::kOk);
    }
    case Command::kSetExposureTime: {
      if (n != 4) return reply(ReplyStatus::kBadLength);
      const std::uint32_t us = pico_flexx::get_u32(p);
      if (us == 0 || us > use_cases[use_case_index].max_exposure_us) {
        return reply(ReplyStatus::kOutOfRange);
      }
      if (exposure_automatic) return reply(ReplyStatus::kWrongMode);
      exposure_us = us;
      return reply(ReplyStatus::kOk);
    }
    case Command::kStartStream: {
      if (n != 0) return reply(ReplyStatus::kBadLength);
      if (!streaming) {
        streaming = true;
        stream_start_us = clock->now_us();
        frames_due_so_far = 0;
      }
      return reply(ReplyStatus::kOk);
    }
    case Command::kStopStream: {
      if (n != 0) return reply(ReplyStatus::kBadLength);
      // The imager stops and its FIFO is flushed: a frame part sent is
      // not finished later.
      streaming = false;
      frame_active = false;
      zero_length_pending = false;
      return reply(ReplyStatus::kOk);
    }
  }
  reply(ReplyStatus::kUnknownCommand);
}

void EmulatedPicoFlexx::Impl::begin_frame(std::int64_t capture_host_us) {
  std::size_t use_case_count = 0;
  const hal::UseCase& use_case = hal::use_cases(&use_case_count)[use_case_index];
  raw.mode = use_case.raw_frames == 9 ? tof::Mode::kMode9 : tof::Mode::kMode5;
  raw.exposure_us = exposure_automatic ? use_case.max_exposure_us : exposure_us;
  source->fill(sequence, capture_host_us, use_case, exposure_automatic ? 0 : exposure_us, &raw);

  pico_flexx::FrameHeader h;
  h.sequence = sequence;
  h.raw_images = use_case.raw_frames;
  h.payload_bytes = static_cast<std::uint32_t>(h.raw_images * tof::kPixels * 2);
  h.use_case_index = static_cast<std::uint8_t>(use_case_index);
  h.width_px = tof::kWidthPx;
  h.height_px = tof::kHeightPx;
  h.exposure_us = raw.exposure_us;
  h.temperature_centi_c = static_cast<std::int16_t>(raw.sensor_temperature_c * 100.0f);
  // The camera's clock: time since power-up, config.clock_ppm fast.
  const std::int64_t since_power_up_us = capture_host_us - power_up_us;
  h.capture_time_us = static_cast<std::uint64_t>(
      since_power_up_us +
      static_cast<std::int64_t>(static_cast<double>(since_power_up_us) * config.clock_ppm * 1e-6));
  capture_log[captures_logged++ % kCaptureLog] = {sequence, capture_host_us};
  std::uint8_t* payload = frame_bytes.data() + pico_flexx::kFrameHeaderBytes;
  std::memcpy(payload, raw.image(0), h.payload_bytes);
  h.payload_checksum = pico_flexx::fletcher32(payload, h.payload_bytes);
  pico_flexx::encode_frame_header(h, frame_bytes.data());
  frame_length = pico_flexx::kFrameHeaderBytes + h.payload_bytes;
  if (corrupt_frames > 0) {
    --corrupt_frames;
    ++counts.frames_corrupted;
    payload[h.payload_bytes / 3] ^= 0x01;
  }
  if (corrupt_headers > 0) {
    --corrupt_headers;
    ++counts.headers_corrupted;
    frame_bytes[40] ^= 0x01;  // the payload checksum's field: the header CRC no longer matches
  }
  if (short_frames > 0) {
    --short_frames;
    ++counts.frames_shortened;
    frame_length /= 2;
  }
  frame_sent = 0;
  frame_active = true;
  ++sequence;
}

void EmulatedPicoFlexx::Impl::feed_stream() {
  // A halted endpoint fails every transfer until the halt is cleared.
  while (stream_halted && !stream_urbs.empty()) {
    usbdevfs_urb* urb = stream_urbs.front();
    stream_urbs.pop_front();
    urb->status = -EPIPE;
    urb->actual_length = 0;
    done_urbs.push_back(urb);
  }
  while (!stream_urbs.empty() && (frame_active || zero_length_pending)) {
    usbdevfs_urb* urb = stream_urbs.front();
    stream_urbs.pop_front();
    urb->status = 0;
    if (!frame_active) {
      urb->actual_length = 0;  // ends a frame that filled its last transfer
      zero_length_pending = false;
      done_urbs.push_back(urb);
      continue;
    }
    const std::size_t left = frame_length - frame_sent;
    const std::size_t room = static_cast<std::size_t>(urb->buffer_length);
    const std::size_t n = left < room ? left : room;
    std::memcpy(urb->buffer, frame_bytes.data() + frame_sent, n);
    urb->actual_length = static_cast<int>(n);
    frame_sent += n;
    if (frame_sent == frame_length) {
      frame_active = false;
      ++counts.frames_sent;
      zero_length_pending = n == room;
    }
    done_urbs.push_back(urb);
  }
}

void EmulatedPicoFlexx::Impl::feed_replies(std::int64_t now_us) {
  while (!replies.empty() && !reply_urbs.empty() && replies.front().ready_us <= now_us) {
    usbdevfs_urb* urb = reply_urbs.front();
    reply_urbs.pop_front();
    const std::vector<std::uint8_t>& bytes = replies.front().bytes;
    const std::size_t n = bytes.size() < static_cast<std::size_t>(urb->buffer_length)
                              ? bytes.size()
                              : static_cast<std::size_t>(urb->buffer_length);
    std::memcpy(urb->buffer, bytes.data(), n);
    urb->actual_length = static_cast<int>(n);
    urb->status = n < bytes.size() ? -EOVERFLOW : 0;
    replies.pop_front();
    done_urbs.push_back(urb);
  }
}

void EmulatedPicoFlexx::Impl::advance(std::int64_t now_us) {
  feed_replies(now_us);
  if (streaming && !silent && !frame_active && !zero_length_pending && !stream_halted) {
    std::size_t use_case_count = 0;
    const hal::UseCase& use_case = hal::use_cases(&use_case_count)[use_case_index];
    const std::int64_t period_us = hal::frame_period_us(use_case);
    const std::uint64_t due =
        static_cast<std::uint64_t>((now_us - stream_start_us) / period_us) + 1;
    // The imager reads frames out into a FIFO of kFifoFrames; what the
    // host does not take in time is lost at the camera, and the sequence
    // numbers say so.
    std::uint64_t backlog = due > frames_due_so_far ? due - frames_due_so_far : 0;
    if (backlog > kFifoFrames) {
      const std::uint64_t dropped = backlog - kFifoFrames;
      counts.frames_dropped_no_transfer += dropped;
      sequence += static_cast<std::uint32_t>(dropped);
      frames_due_so_far += dropped;
      backlog = kFifoFrames;
    }
    if (backlog > 0 && !stream_urbs.empty()) {
      // The oldest frame in the FIFO was read out when it fell due, not now.
      const std::int64_t capture_host_us =
          stream_start_us + static_cast<std::int64_t>(frames_due_so_far) * period_us;
      ++frames_due_so_far;
      begin_frame(capture_host_us);
    }
  }
  feed_stream();
}

}  // namespace sim_hal
