#pragma once
// The royale SDK's container and id types. The SDK ships its own String,
// Vector and Pair classes; here they extend the standard ones with the
// SDK's own calls (String.hpp, Vector.hpp, Pair.hpp), so an application's
// uses of either interface read the same.
#include <cstdint>

#include "royale/Pair.hpp"
#include "royale/String.hpp"
#include "royale/Vector.hpp"

namespace royale {

// A use case's stream. This camera has one stream per use case; its frames
// carry 0xdefa (royale's id for a use case's first stream), and as in
// royale, 0 also names it in the calls that take a stream id.
using StreamId = std::uint16_t;

}  // namespace royale
