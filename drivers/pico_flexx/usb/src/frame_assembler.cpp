#include "pico_flexx/frame_assembler.hpp"

#include <cstring>

#include "hal/use_case.hpp"

namespace pico_flexx {

static_assert(__BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__,
              "payload bytes are copied into the frame's samples as they are");
static_assert(kMaxRawPayloadBytes() == tof::kMaxRawImages * tof::kPixels * sizeof(std::uint16_t),
              "a MODE_9 payload fills the raw frame's buffer exactly");

namespace {

// Whether a transfer begins with the frame header's magic. 12-bit samples
// never form it at a transfer's start (their odd bytes are at most 0x0F),
// so this marks the start of a frame, whatever state its header is in.
bool starts_with_magic(const std::uint8_t* data, std::size_t length) {
  return length >= sizeof(std::uint32_t) && get_u32(data) == kFrameMagic;
}

}  // namespace

const char* to_string(AssemblyEvent event) {
  switch (event) {
    case AssemblyEvent::kNone:
      return "NONE";
    case AssemblyEvent::kFrameReady:
      return "FRAME_READY";
    case AssemblyEvent::kDropped:
      return "DROPPED";
    case AssemblyEvent::kDiscarded:
      return "DISCARDED";
  }
  return "UNKNOWN_ASSEMBLY_EVENT";
}

void FrameAssembler::restart() {
  phase_ = Phase::kBetweenFrames;
  received_bytes_ = 0;
  have_sequence_ = false;
}

AssemblyEvent FrameAssembler::on_transfer(const std::uint8_t* data, std::size_t length,
                                          std::size_t capacity) {
  ++counts_.transfers;
  started_frame_ = false;
  if (length == 0) {
    // The end of a frame that filled its last transfer exactly; in the
    // middle of a frame it cuts the frame short.
    ++counts_.zero_length_transfers;
    const Phase was = phase_;
    phase_ = Phase::kBetweenFrames;
    if (was == Phase::kInFrame) return drop(&counts_.frames_short, received_bytes_);
    return AssemblyEvent::kNone;
  }
  // A frame's start inside another frame means that frame lost its end.
  if (phase_ != Phase::kBetweenFrames && starts_with_magic(data, length)) {
    const bool cut_short = phase_ == Phase::kInFrame;
    const std::size_t cut_bytes = received_bytes_;
    phase_ = Phase::kBetweenFrames;
    const AssemblyEvent next = start_frame(data, length, capacity);
    if (!cut_short) return next;
    drop(&counts_.frames_short, cut_bytes);
    return next == AssemblyEvent::kFrameReady ? next : AssemblyEvent::kDropped;
  }
  switch (phase_) {
    case Phase::kInFrame:
      return continue_frame(data, length, capacity);
    case Phase::kSkippingFrame:
      return skip_transfer(data, length, capacity);
    case Phase::kBetweenFrames:
      break;
  }
  return start_frame(data, length, capacity);
}

AssemblyEvent FrameAssembler::start_frame(const std::uint8_t* data, std::size_t length,
                                          std::size_t capacity) {
  FrameHeader h;
  const ParseStatus s = parse_frame_header(data, length, &h);
  if (s != ParseStatus::kOk) {
    counts_.last_header_error = s;
    if (!starts_with_magic(data, length)) {
      // No frame starts here: stray bytes, not a frame lost.
      ++counts_.transfers_discarded;
      counts_.bytes_discarded += length;
      return AssemblyEvent::kDiscarded;
    }
    return drop_and_skip(&counts_.frames_bad_header, length, length, capacity);
  }
  header_ = h;
  phase_ = Phase::kInFrame;
  started_frame_ = true;
  received_bytes_ = 0;
  return continue_frame(data + kFrameHeaderBytes, length - kFrameHeaderBytes,
                        capacity - kFrameHeaderBytes);
}

AssemblyEvent FrameAssembler::continue_frame(const std::uint8_t* data, std::size_t length,
                                             std::size_t capacity) {
  const std::size_t remaining = header_.payload_bytes - received_bytes_;
  if (length > remaining) {
    return drop_and_skip(&counts_.frames_overrun, received_bytes_ + length, length, capacity);
  }
  std::memcpy(payload_bytes() + received_bytes_, data, length);
  received_bytes_ += length;
  if (received_bytes_ == header_.payload_bytes) return finish_frame();
  if (length < capacity) {
    // A short transfer before the frame's size: the camera ended it early.
    phase_ = Phase::kBetweenFrames;
    return drop(&counts_.frames_short, received_bytes_);
  }
  return AssemblyEvent::kNone;
}

AssemblyEvent FrameAssembler::skip_transfer(const std::uint8_t*, std::size_t length,
                                            std::size_t capacity) {
  // The refused frame was counted at its start; its end is a short transfer.
  counts_.bytes_discarded += length;
  if (length < capacity) phase_ = Phase::kBetweenFrames;
  return AssemblyEvent::kNone;
}

AssemblyEvent FrameAssembler::finish_frame() {
  phase_ = Phase::kBetweenFrames;
  if (fletcher32(payload_bytes(), header_.payload_bytes) != header_.payload_checksum) {
    return drop(&counts_.frames_corrupt, header_.payload_bytes);
  }
  // Sequence numbers wrap at 2^32 (at 45 fps after 3 years): compare the
  // signed difference.
  const std::int32_t ahead = static_cast<std::int32_t>(header_.sequence - last_sequence_);
  if (have_sequence_ && ahead <= 0)
    return drop(&counts_.frames_out_of_order, header_.payload_bytes);
  if (have_sequence_) counts_.frames_missed += static_cast<std::uint32_t>(ahead - 1);
  have_sequence_ = true;
  last_sequence_ = header_.sequence;

  std::size_t use_case_count = 0;
  const hal::UseCase* use_cases = hal::use_cases(&use_case_count);
  target_->mode =
      use_cases[header_.use_case_index].raw_frames == 9 ? tof::Mode::kMode9 : tof::Mode::kMode5;
  target_->frame_id = header_.sequence;
  target_->exposure_us = header_.exposure_us;
  target_->sensor_temperature_c = static_cast<float>(header_.temperature_centi_c) / 100.0f;
  ++counts_.frames_complete;
  return AssemblyEvent::kFrameReady;
}

AssemblyEvent FrameAssembler::drop(std::uint64_t* counter, std::size_t bytes) {
  ++*counter;
  counts_.bytes_discarded += bytes;
  return AssemblyEvent::kDropped;
}

AssemblyEvent FrameAssembler::drop_and_skip(std::uint64_t* counter, std::size_t bytes,
                                            std::size_t length, std::size_t capacity) {
  phase_ = length < capacity ? Phase::kBetweenFrames : Phase::kSkippingFrame;
  return drop(counter, bytes);
}

}  // namespace pico_flexx
