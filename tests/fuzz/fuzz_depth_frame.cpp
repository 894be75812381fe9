// libFuzzer: the DEPTH_FRAME byte check and decode on arbitrary bytes. It
// must never read out of bounds nor allocate beyond its buffers, and a
// frame it accepts must be whole: width x height points in every plane.
// The first byte picks the receiver's capacity (1 to 128 points, so that
// whole frames are within the fuzzer's reach) and, by its top bit, whether
// the type's fingerprint is put in front of the rest (else the rest is the
// message as it is).
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <vector>

#include "fsw_app/depth_frame_msg.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const std::size_t max_points = 1 + (data[0] & 0x7f);
  std::vector<std::uint8_t> bytes;
  if ((data[0] & 0x80) == 0) {
    const std::uint64_t hash = static_cast<std::uint64_t>(hrp::depth_frame_t::getHash());
    for (int k = 7; k >= 0; --k) bytes.push_back(static_cast<std::uint8_t>(hash >> (8 * k)));
  }
  bytes.insert(bytes.end(), data + 1, data + size);
  hrp::depth_frame_t msg;
  fsw_app::reserve_points(&msg, max_points);
  const fsw_app::FrameMsgStatus status =
      fsw_app::decode_depth_frame(bytes.data(), bytes.size(), max_points, &msg);
  if (status != fsw_app::FrameMsgStatus::kOk) return 0;
  const auto n = static_cast<std::size_t>(msg.num_points);
  if (msg.width <= 0 || msg.height <= 0 || n != static_cast<std::size_t>(msg.width) * msg.height ||
      n > max_points || msg.x_m.size() != n || msg.confidence.size() != n ||
      msg.gray_value.size() != n || bytes.size() != fsw_app::depth_frame_encoded_size(n)) {
    std::abort();
  }
  std::vector<hal::DepthPoint> points(n);
  hal::DepthFrame frame;
  fsw_app::from_msg(msg, points.data(), &frame);
  if (frame.width * frame.height != n) std::abort();
  return 0;
}
