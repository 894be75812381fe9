#include "estimator/handrail_types.hpp"

#include <cmath>

namespace estimator {

int match_handrail_type(const DetectorConfig& cfg, float beam_length_m) {
  int best = -1;
  float best_distance = INFINITY;
  for (std::uint32_t k = 0; k < cfg.handrail_type_count && k < kMaxHandrailTypes; ++k) {
    const float ratio = beam_length_m / cfg.handrail_types[k].bar_length_m;
    if (!(ratio >= cfg.beam_length_min_ratio && ratio <= cfg.beam_length_max_ratio)) continue;
    // By ratio, so a 0.20 m bar 4 cm short is as near as a 1 m bar 20 cm
    // short: the end detection errs in proportion to what it walks.
    const float distance = std::fabs(std::log(ratio));
    if (distance < best_distance) {
      best_distance = distance;
      best = static_cast<int>(k);
    }
  }
  return best;
}

bool beam_length_matches(const DetectorConfig& cfg, float beam_length_m) {
  if (cfg.handrail_type_count > 0) return match_handrail_type(cfg, beam_length_m) >= 0;
  const float length_m = cfg.handrail.bar_length_m;
  return beam_length_m >= cfg.beam_length_min_ratio * length_m &&
         beam_length_m <= cfg.beam_length_max_ratio * length_m;
}

float longest_handrail_m(const DetectorConfig& cfg) {
  if (cfg.handrail_type_count == 0) return cfg.handrail.bar_length_m;
  float longest = 0.0f;
  for (std::uint32_t k = 0; k < cfg.handrail_type_count && k < kMaxHandrailTypes; ++k) {
    longest = std::fmax(longest, cfg.handrail_types[k].bar_length_m);
  }
  return longest;
}

float shortest_partial_bar_m(const DetectorConfig& cfg) {
  float shortest = cfg.handrail.bar_length_m;
  if (cfg.handrail_type_count > 0) {
    shortest = INFINITY;
    for (std::uint32_t k = 0; k < cfg.handrail_type_count && k < kMaxHandrailTypes; ++k) {
      shortest = std::fmin(shortest, cfg.handrail_types[k].bar_length_m);
    }
  }
  return std::fmin(cfg.min_visible_length_m, cfg.min_visible_fraction * shortest);
}

}  // namespace estimator
