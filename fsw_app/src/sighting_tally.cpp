#include "fsw_app/sighting_tally.hpp"

#include <algorithm>

#include "estimator/handrail_types.hpp"
#include "fsw_app/input_checks.hpp"

namespace fsw_app {

void SightingTally::deliver(const void* data, std::uint32_t size, std::int64_t /*now_us*/) {
  InputReject why = InputReject::kUndecodable;
  if (!decode_and_check(data, size, &scratch_, &why)) {
    std::lock_guard<std::mutex> lock(mutex_);
    ++counts_.rejected;
    return;
  }
  add(scratch_);
}

void SightingTally::add(const hrp::handrail_estimate_t& m) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (m.state < hrp::handrail_estimate_t::STATE_NH ||
      m.state > hrp::handrail_estimate_t::STATE_NE) {
    ++counts_.rejected;
    return;
  }
  const bool first_be = counts_.by_state[hrp::handrail_estimate_t::STATE_BE] == 0;
  ++counts_.by_state[m.state];
  if (m.state != hrp::handrail_estimate_t::STATE_BE) return;
  const float length_m = static_cast<float>(m.bar_length_m);
  counts_.be_length_min_m = first_be ? length_m : std::min(counts_.be_length_min_m, length_m);
  counts_.be_length_max_m = first_be ? length_m : std::max(counts_.be_length_max_m, length_m);
  const int type = estimator::match_handrail_type(cfg_, length_m);
  ++counts_.be_by_type[type >= 0 ? static_cast<std::uint32_t>(type) : estimator::kMaxHandrailTypes];
}

SightingCounts SightingTally::counts() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return counts_;
}

SightingReport SightingTally::report() const {
  SightingReport r;
  r.counts = counts();
  r.type_count = std::min(cfg_.handrail_type_count, estimator::kMaxHandrailTypes);
  for (std::uint32_t k = 0; k < r.type_count; ++k) r.type_names[k] = cfg_.handrail_types[k].name;
  return r;
}

}  // namespace fsw_app
