#include "estimator/localization/history.hpp"

namespace estimator::localization {

HistoryEntry& ImuHistory::push(const ImuSample& s) {
  if (size_ == kHistoryCapacity) {
    head_ = (head_ + 1) % kHistoryCapacity;
    --size_;
  }
  ++size_;
  HistoryEntry& e = newest();
  e.imu = s;
  e.has_state = false;
  return e;
}

int ImuHistory::find_at_or_before(std::int64_t t_us) const {
  // Binary search: times increase from oldest to newest.
  int lo = 0, hi = size_;  // first index with time > t_us lies in [lo, hi]
  while (lo < hi) {
    const int mid = (lo + hi) / 2;
    if (at(mid).imu.t_us <= t_us) {
      lo = mid + 1;
    } else {
      hi = mid;
    }
  }
  return lo - 1;
}

int ImuHistory::find_after(std::int64_t t_us) const {
  return find_at_or_before(t_us) + 1;
}

int MeasurementStore::insert(const StoredMeasurement& m, bool* evicted,
                             std::int64_t* evicted_t_us) {
  *evicted = false;
  if (size_ == kMaxStoredMeasurements) {
    *evicted = true;
    *evicted_t_us = items_[0].t_us;
    for (int i = 1; i < size_; ++i) {
      items_[static_cast<std::size_t>(i - 1)] = items_[static_cast<std::size_t>(i)];
    }
    --size_;
  }
  // Usually the newest: found at once from the end.
  int pos = size_;
  while (pos > 0) {
    const StoredMeasurement& prev = items_[static_cast<std::size_t>(pos - 1)];
    if (prev.t_us < m.t_us || (prev.t_us == m.t_us && prev.seq < m.seq)) break;
    items_[static_cast<std::size_t>(pos)] = prev;
    --pos;
  }
  items_[static_cast<std::size_t>(pos)] = m;
  ++size_;
  return pos;
}

void MeasurementStore::drop_before(std::int64_t t_us) {
  int n = 0;
  while (n < size_ && items_[static_cast<std::size_t>(n)].t_us < t_us) ++n;
  if (n == 0) return;
  for (int i = n; i < size_; ++i) {
    items_[static_cast<std::size_t>(i - n)] = items_[static_cast<std::size_t>(i)];
  }
  size_ -= n;
}

int MeasurementStore::first_after(std::int64_t t_us) const {
  int i = 0;
  while (i < size_ && items_[static_cast<std::size_t>(i)].t_us <= t_us) ++i;
  return i;
}

}  // namespace estimator::localization
