#pragma once
// A small, fully specified generator (SplitMix64): the same sequence on every
// platform and compiler, unlike std:: distributions.
#include <cstdint>

namespace estimator {

class Random {
 public:
  explicit Random(std::uint64_t seed = 0) : state_(seed) {}
  void reseed(std::uint64_t seed) { state_ = seed; }
  std::uint64_t next() {
    std::uint64_t z = (state_ += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
  }
  // Uniform in [0, n); n > 0. The modulo bias is below 2^-40 for our sizes.
  std::uint32_t below(std::uint32_t n) { return static_cast<std::uint32_t>(next() % n); }

 private:
  std::uint64_t state_;
};

}  // namespace estimator
