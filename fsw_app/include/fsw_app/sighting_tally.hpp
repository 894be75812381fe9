#pragma once
// What the estimator reported over a run, for the run's summary: how many
// frames in each handrail state, and for the frames with both ends seen the
// range of the bar's measured length and the ISS type each matched. One
// handrail in view should give one type; a mix says the detector measured
// some other structure, or part of the bar, as a whole handrail (a HIL
// run once saw the 0.55 m round rail reported as 8.5 in on its first
// frames, and the filter took it). A receiver on HANDRAIL_ESTIMATE (LcmHub
// delivers to it on the dispatcher thread); fixed memory.
#include <cstdint>
#include <mutex>

#include "estimator/config.hpp"
#include "hrp/handrail_estimate_t.hpp"

namespace fsw_app {

struct SightingCounts {
  std::uint64_t by_state[4] = {};  // NH, BE, OE, NE (handrail_estimate_t's STATE_*)
  std::uint64_t rejected = 0;      // did not decode or failed the input checks
  float be_length_min_m = 0.0f;    // over the BE frames; 0 when there were none
  float be_length_max_m = 0.0f;
  // BE frames per configured ISS type (the detector's handrail_types), and
  // the last slot for a length that matched none.
  std::uint64_t be_by_type[estimator::kMaxHandrailTypes + 1] = {};
};

// The counts with the types' names, as the summary reports them.
struct SightingReport {
  SightingCounts counts;
  std::uint32_t type_count = 0;
  const char* type_names[estimator::kMaxHandrailTypes] = {};
};

class SightingTally {
 public:
  explicit SightingTally(const estimator::DetectorConfig& cfg) : cfg_(cfg) {}

  // Dispatcher side: one encoded HANDRAIL_ESTIMATE.
  void deliver(const void* data, std::uint32_t size, std::int64_t now_us);
  // One decoded estimate (what deliver() does after checking it).
  void add(const hrp::handrail_estimate_t& m);
  SightingCounts counts() const;
  SightingReport report() const;

 private:
  estimator::DetectorConfig cfg_;
  mutable std::mutex mutex_;
  SightingCounts counts_;
  hrp::handrail_estimate_t scratch_{};
};

}  // namespace fsw_app
