#pragma once
// The beam-length check of Algorithm 1 against every handrail length the
// configuration knows (the station has four, and the modules' 1 m rails),
// and which one a bar seen end to end is.
#include "estimator/config.hpp"

namespace estimator {

// The index of the known type nearest to a beam length (by ratio), among
// those whose window [beam_length_min_ratio, beam_length_max_ratio] x
// length holds it; -1 if none does or the configuration lists no types.
int match_handrail_type(const DetectorConfig& cfg, float beam_length_m);

// Whether a bar seen end to end has a handrail's length: a known type's,
// or with no types listed, handrail.bar_length_m's.
bool beam_length_matches(const DetectorConfig& cfg, float beam_length_m);

// The longest bar the detector accepts a partial view of.
float longest_handrail_m(const DetectorConfig& cfg);

// The shortest partial view of a bar accepted: min_visible_length_m, or
// min_visible_fraction of the shortest known length where that is less.
float shortest_partial_bar_m(const DetectorConfig& cfg);

}  // namespace estimator
