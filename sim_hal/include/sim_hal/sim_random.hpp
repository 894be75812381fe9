#pragma once
// Deterministic random numbers for the simulator: SplitMix64 with our own
// uniform and Marsaglia's polar normal, so a seed gives identical bytes with
// any standard library.
#include <cmath>
#include <cstdint>

namespace sim_hal {

class SimRandom {
 public:
  explicit SimRandom(std::uint64_t seed) : state_(seed) {}
  std::uint64_t next() {
    std::uint64_t z = (state_ += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
  }
  // Uniform in [0, 1).
  double uniform() { return static_cast<double>(next() >> 11) * 0x1.0p-53; }
  // Standard normal, two at a time by the polar method (no trigonometry:
  // the renderer draws one per pixel). A point in the unit disc is
  // accepted with probability pi / 4, so the loop ends after 1.27 tries on
  // average; the cap only guards against a broken generator.
  double normal() {
    if (has_spare_) {
      has_spare_ = false;
      return spare_;
    }
    double x = 0.0, y = 0.0, s = 0.0;
    for (int tries = 0; tries < 64; ++tries) {
      x = 2.0 * uniform() - 1.0;
      y = 2.0 * uniform() - 1.0;
      s = x * x + y * y;
      if (s > 0.0 && s < 1.0) break;
    }
    if (!(s > 0.0 && s < 1.0)) return 0.0;
    const double k = std::sqrt(-2.0 * std::log(s) / s);
    spare_ = y * k;
    has_spare_ = true;
    return x * k;
  }

 private:
  std::uint64_t state_;
  double spare_ = 0.0;
  bool has_spare_ = false;
};

// Mixes a scenario seed, a frame index and a stream id into one seed.
inline std::uint64_t mix_seed(std::uint64_t seed, std::uint64_t frame, std::uint64_t stream) {
  SimRandom r(seed ^ (frame * 0xd1342543de82ef95ull) ^ (stream * 0x2545f4914f6cdd1dull));
  return r.next();
}

}  // namespace sim_hal
