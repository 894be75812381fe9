#pragma once
// royale::Pair: royale's own pair class, here the standard pair with
// royale's conversions added (toStdPair, fromStdPair).
#include <utility>

namespace royale {

template <typename A, typename B>
class Pair : public std::pair<A, B> {
 public:
  using std::pair<A, B>::pair;
  Pair() = default;
  Pair(const std::pair<A, B>& p)
      : std::pair<A, B>(p) {}  // NOLINT: implicit, so a standard one passes

  std::pair<A, B> toStdPair() const { return *this; }
  static Pair fromStdPair(const std::pair<A, B>& p) { return Pair(p); }
};

}  // namespace royale
