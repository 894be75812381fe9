// libFuzzer: the Dynamixel status parser on arbitrary bytes. It must never
// read or write out of bounds, and every packet it reports must be
// well-formed: its checksum recomputes and its length fits.
#include <cstddef>
#include <cstdint>
#include <cstdlib>

#include "dynamixel/protocol1.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  dynamixel::StatusParser parser;
  for (std::size_t k = 0; k < size; ++k) {
    if (parser.push(data[k]) != dynamixel::ParseEvent::kPacket) continue;
    const dynamixel::StatusPacket& p = parser.packet();
    if (p.n_params > dynamixel::kMaxParams) std::abort();
    // Re-encoding the packet must give bytes that parse back to it.
    std::uint8_t out[dynamixel::kMaxPacket];
    const std::size_t n = dynamixel::encode_status(p.id, p.error, p.params, p.n_params, out);
    dynamixel::StatusParser again;
    dynamixel::ParseEvent last = dynamixel::ParseEvent::kNone;
    for (std::size_t j = 0; j < n; ++j) last = again.push(out[j]);
    if (last != dynamixel::ParseEvent::kPacket || again.packet().n_params != p.n_params) {
      std::abort();
    }
  }
  return 0;
}
