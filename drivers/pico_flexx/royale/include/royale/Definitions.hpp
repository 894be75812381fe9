#pragma once
// The royale SDK's container and id types. The SDK ships its own String,
// Vector and Pair with the standard ones' interface; here they are the
// standard types themselves, so an application's uses (c_str(), size(),
// operator[], push_back, first/second, range-for) read the same.
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace royale {

using String = std::string;

template <typename T>
using Vector = std::vector<T>;

template <typename A, typename B>
using Pair = std::pair<A, B>;

// A use case's stream. This camera has one stream per use case; its frames
// carry 0xdefa (royale's id for a use case's first stream), and as in
// royale, 0 also names it in the calls that take a stream id.
using StreamId = std::uint16_t;

}  // namespace royale
