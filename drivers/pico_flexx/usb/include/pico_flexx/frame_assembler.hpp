#pragma once
// Raw frames back from the stream endpoint's transfers. The camera sends
// each frame as its 64-byte header and payload back to back and ends it
// with a short (or zero-length) transfer, so a frame always starts a
// transfer. The assembler copies payload bytes straight into a
// tof::RawFrame (the wire's layout is the frame's: planar 16-bit
// little-endian samples) and hands a frame on only when its header,
// size, checksum and sequence number are right; anything else is dropped
// and counted by reason, once per frame: the rest of a refused frame's
// transfers is skipped up to its end. A transfer that starts no frame
// (no magic where a header should be) is not a frame and is counted
// apart. Pure: no I/O, no clock, no allocation.
#include <cstddef>
#include <cstdint>

#include "pico_flexx/usb_protocol.hpp"
#include "tof/raw_frame.hpp"

namespace pico_flexx {

struct AssemblerCounts {
  std::uint64_t transfers = 0;
  std::uint64_t zero_length_transfers = 0;
  std::uint64_t frames_complete = 0;      // handed on
  std::uint64_t frames_short = 0;         // ended before their size
  std::uint64_t frames_corrupt = 0;       // payload checksum wrong
  std::uint64_t frames_bad_header = 0;    // the magic, then a header that does not parse
  std::uint64_t frames_overrun = 0;       // more bytes than the header said, no frame end
  std::uint64_t frames_out_of_order = 0;  // sequence not after the last one handed on
  // Sequence gaps between frames handed on: frames the camera never sent,
  // and the frames dropped above (a dropped frame's sequence is not taken).
  std::uint64_t frames_missed = 0;
  // Transfers with no magic where a frame should start (stray bytes, the
  // tail of a frame whose start was lost): not frames, so not in dropped().
  std::uint64_t transfers_discarded = 0;
  std::uint64_t bytes_discarded = 0;  // bytes of dropped frames and discarded transfers
  ParseStatus last_header_error = ParseStatus::kOk;
  // Frames refused, each counted once.
  std::uint64_t dropped() const {
    return frames_short + frames_corrupt + frames_bad_header + frames_overrun + frames_out_of_order;
  }
};

enum class AssemblyEvent : std::uint8_t {
  kNone,        // bytes taken, no frame finished
  kFrameReady,  // target() holds a complete, checked frame
  kDropped,     // a frame was refused; counts say why
  kDiscarded,   // a transfer that is no frame's was discarded
};
const char* to_string(AssemblyEvent event);

class FrameAssembler {
 public:
  // Frames are written into `target` (not owned; it must outlive this).
  explicit FrameAssembler(tof::RawFrame* target) : target_(target) {}

  // One completed transfer: `length` bytes received into a transfer of
  // `capacity` bytes (length < capacity marks the end of a frame).
  AssemblyEvent on_transfer(const std::uint8_t* data, std::size_t length, std::size_t capacity);

  // Forgets the frame in progress and the last sequence number (after the
  // stream restarts: a reconnect, a reset).
  void restart();
  // Forgets only the frame in progress (its transfers were cancelled); the
  // sequence check goes on.
  void abandon_frame() { phase_ = Phase::kBetweenFrames; }

  // Whether the last transfer began a frame (its header parsed), between
  // frames or inside one whose end was lost.
  bool started_frame() const { return started_frame_; }
  const AssemblerCounts& counts() const { return counts_; }
  const FrameHeader& last_header() const { return header_; }
  tof::RawFrame* target() { return target_; }

 private:
  // Where the next transfer falls: at a frame's start, inside a frame being
  // copied, or inside a refused frame whose remaining transfers are skipped.
  enum class Phase : std::uint8_t { kBetweenFrames, kInFrame, kSkippingFrame };

  AssemblyEvent start_frame(const std::uint8_t* data, std::size_t length, std::size_t capacity);
  AssemblyEvent continue_frame(const std::uint8_t* data, std::size_t length, std::size_t capacity);
  AssemblyEvent finish_frame();
  AssemblyEvent skip_transfer(const std::uint8_t* data, std::size_t length, std::size_t capacity);
  AssemblyEvent drop(std::uint64_t* counter, std::size_t bytes);
  // Drops the frame and skips its transfers up to its end, unless this
  // transfer (`length` of `capacity`) already ended it.
  AssemblyEvent drop_and_skip(std::uint64_t* counter, std::size_t bytes, std::size_t length,
                              std::size_t capacity);
  std::uint8_t* payload_bytes() { return reinterpret_cast<std::uint8_t*>(target_->image(0)); }

  tof::RawFrame* target_;
  AssemblerCounts counts_;
  FrameHeader header_;
  Phase phase_ = Phase::kBetweenFrames;
  std::size_t received_bytes_ = 0;  // payload bytes of the frame in progress
  bool have_sequence_ = false;
  bool started_frame_ = false;
  std::uint32_t last_sequence_ = 0;
};

}  // namespace pico_flexx
