#pragma once
// Between the HAL's depth frames and the DEPTH_FRAME message (depth_frame_t),
// which carries frames between processes and into LCM logs.
//
// Incoming bytes are checked before LCM decodes them: the generated decoder
// sizes its arrays from the message's own count, so a corrupt count would
// have it allocate gigabytes (and throw) before it found the bytes missing.
#include <cstddef>
#include <cstdint>

#include "hal/depth_frame.hpp"
#include "hrp/depth_frame_t.hpp"

namespace fsw_app {

enum class FrameMsgStatus : std::uint8_t {
  kOk,
  kTruncated,      // fewer bytes than the header, or than the point count needs
  kWrongType,      // the fingerprint is not depth_frame_t's
  kBadSize,        // width or height not positive, or width * height != num_points
  kTooLarge,       // more points than this receiver's buffers hold
  kTrailingBytes,  // more bytes than the point count accounts for
  kDecodeFailed,   // LCM's decoder refused it
};
const char* to_string(FrameMsgStatus status);

// The encoded size of a frame of n points.
std::size_t depth_frame_encoded_size(std::size_t n_points);

// Gives the message's arrays room for max_points once, so that filling or
// decoding frames up to that size later does not allocate.
void reserve_points(hrp::depth_frame_t* msg, std::size_t max_points);

// Copies a frame into the message (arrays resized within their reserve).
// utime is the caller's (publish time).
void to_msg(const hal::DepthFrame& frame, hrp::depth_frame_t* msg);

// Checks encoded bytes, then decodes them into `msg` (reserved for
// max_points). Nothing is decoded unless the bytes are a well-formed frame
// of at most max_points points.
FrameMsgStatus decode_depth_frame(const void* data, std::size_t size, std::size_t max_points,
                                  hrp::depth_frame_t* msg);

// Fills `points` (capacity >= msg.num_points) and `frame` from a decoded
// message; frame->points points into `points`.
void from_msg(const hrp::depth_frame_t& msg, hal::DepthPoint* points, hal::DepthFrame* frame);

}  // namespace fsw_app
