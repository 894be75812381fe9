#pragma once
// The short history that lets late measurements be applied at their capture
// time: a ring of the last kHistoryCapacity IMU samples, each with the state
// and covariance the filter had after it, and the accepted measurements of
// that window, kept in time order to be re-applied when a later-arriving,
// earlier-captured measurement makes the filter re-propagate over them.
// Fixed memory: both are arrays sized at compile time.
#include <array>
#include <cstdint>

#include "estimator/localization/config.hpp"
#include "estimator/localization/handrail_update.hpp"
#include "estimator/localization/measurements.hpp"
#include "estimator/localization/state.hpp"
#include "estimator/localization/status.hpp"

namespace estimator::localization {

struct HistoryEntry {
  ImuSample imu;
  NominalState x;  // after this sample (meaningful when has_state)
  Covariance P = Covariance::Identity();
  bool has_state = false;  // false before initialisation
};

class ImuHistory {
 public:
  int size() const { return size_; }
  bool empty() const { return size_ == 0; }
  void clear() { head_ = size_ = 0; }
  // Appends a sample (the oldest is dropped when full); returns its entry,
  // without state.
  HistoryEntry& push(const ImuSample& s);
  // 0 is the oldest, size() - 1 the newest.
  HistoryEntry& at(int i) { return ring_[slot(i)]; }
  const HistoryEntry& at(int i) const { return ring_[slot(i)]; }
  HistoryEntry& newest() { return at(size_ - 1); }
  const HistoryEntry& newest() const { return at(size_ - 1); }
  // The newest entry with imu.t_us <= t_us; -1 when all are later.
  int find_at_or_before(std::int64_t t_us) const;
  // The oldest entry with imu.t_us > t_us; size() when none.
  int find_after(std::int64_t t_us) const;

 private:
  std::size_t slot(int i) const { return static_cast<std::size_t>((head_ + i) % kHistoryCapacity); }
  std::array<HistoryEntry, kHistoryCapacity> ring_{};
  int head_ = 0;
  int size_ = 0;
};

// An accepted measurement, as re-applied on a re-propagation.
struct StoredMeasurement {
  MeasurementKind kind = MeasurementKind::kGpPose;
  std::int64_t t_us = 0;             // where it was applied
  std::uint32_t seq = 0;             // arrival order, for equal times
  std::uint32_t map_generation = 0;  // handrail: the map it was made against
  GpPose gp;
  SelectedFeatures handrail;
  // Not a measurement: the map put into the state at t_us (map_state.hpp),
  // surveyed or from sightings, re-done on every re-propagation across it.
  bool map_attach = false;
  HandrailMap map;
};

// Accepted measurements in (t_us, seq) order.
class MeasurementStore {
 public:
  int size() const { return size_; }
  void clear() { size_ = 0; }
  const StoredMeasurement& at(int i) const { return items_[static_cast<std::size_t>(i)]; }
  // Inserts in order and returns its index. When full the oldest is dropped
  // first: *evicted is then set, with its time in *evicted_t_us.
  int insert(const StoredMeasurement& m, bool* evicted, std::int64_t* evicted_t_us);
  // Drops those applied before t_us (older than the history).
  void drop_before(std::int64_t t_us);
  // The first index with t_us > t; size() when none.
  int first_after(std::int64_t t_us) const;

 private:
  std::array<StoredMeasurement, kMaxStoredMeasurements> items_{};
  int size_ = 0;
};

}  // namespace estimator::localization
