#pragma once
// Deterministic random numbers for the simulator: SplitMix64 with our own
// uniform and a ziggurat normal, so a seed gives identical bytes with
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
  // Standard normal by Marsaglia and Tsang's ziggurat: the density is cut
  // into 128 layers of equal area; one 64-bit draw picks a layer, a sign
  // and a position in the layer, and about 99 % of draws are accepted by
  // one comparison (the renderer draws one per pixel; the polar method
  // needed a logarithm per pair and a rejection loop that the branch
  // predictor cannot learn). The cap on tries only guards against a broken
  // generator: a try fails with probability about 1 %.
  double normal() {
    const ZigguratTables& z = ziggurat_tables();
    for (int tries = 0; tries < 64; ++tries) {
      const std::uint64_t bits = next();
      const unsigned layer = static_cast<unsigned>(bits & 127u);
      // Arithmetic, not a branch: the sign is a coin toss no predictor learns.
      const double sign = 1.0 - 2.0 * static_cast<double>((bits >> 7) & 1u);
      const double x = static_cast<double>(bits >> 11) * 0x1.0p-53 * z.x[layer];
      if (x < z.x[layer + 1]) return sign * x;  // under the curve whatever the height
      if (layer == 0) return sign * normal_tail(z.x[1]);
      // In the sliver between the layer's core and its outer edge: accept
      // a point under the density.
      const double y = z.f[layer] + uniform() * (z.f[layer + 1] - z.f[layer]);
      if (y < std::exp(-0.5 * x * x)) return sign * x;
    }
    return 0.0;
  }

 private:
  // Layer k spans x in [0, x[k]] and density heights [f[k], f[k + 1]];
  // x[1] is where the tail starts, x[0] the base layer's width (tail
  // included), x[128] = 0.
  struct ZigguratTables {
    double x[129];
    double f[129];
  };
  static const ZigguratTables& ziggurat_tables() {
    static const ZigguratTables tables = [] {
      constexpr double kTailStart = 3.442619855899, kLayerArea = 9.91256303526217e-3;
      ZigguratTables z{};
      auto density = [](double x) { return std::exp(-0.5 * x * x); };
      z.x[0] = kLayerArea / density(kTailStart);
      z.x[1] = kTailStart;
      for (int k = 1; k < 127; ++k) {
        z.x[k + 1] = std::sqrt(-2.0 * std::log(kLayerArea / z.x[k] + density(z.x[k])));
      }
      z.x[128] = 0.0;
      for (int k = 0; k <= 128; ++k) z.f[k] = density(z.x[k]);
      return z;
    }();
    return tables;
  }
  // The normal's tail beyond `start`, by Marsaglia's exponential method.
  double normal_tail(double start) {
    for (int tries = 0; tries < 64; ++tries) {
      const double a = -std::log(1.0 - uniform()) / start;
      const double b = -std::log(1.0 - uniform());
      if (b + b >= a * a) return start + a;
    }
    return start;
  }

  std::uint64_t state_;
};

// Mixes a scenario seed, a frame index and a stream id into one seed.
inline std::uint64_t mix_seed(std::uint64_t seed, std::uint64_t frame, std::uint64_t stream) {
  SimRandom r(seed ^ (frame * 0xd1342543de82ef95ull) ^ (stream * 0x2545f4914f6cdd1dull));
  return r.next();
}

}  // namespace sim_hal
