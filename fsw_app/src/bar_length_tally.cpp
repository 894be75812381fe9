#include "fsw_app/bar_length_tally.hpp"

#include <algorithm>
#include <cmath>

namespace fsw_app {

bool BarLengthTally::add_both_ends(double length_m) {
  if (!std::isfinite(length_m) || length_m < kMinLengthM || length_m > kMaxLengthM) return false;
  lengths_m_[static_cast<std::size_t>(next_)] = length_m;
  next_ = (next_ + 1) % kWindow;
  count_ = std::min(count_ + 1, kWindow);
  return true;
}

double BarLengthTally::length_m() const {
  if (count_ < kMinAgreeing) return -1.0;
  // Insertion into a sorted copy: five at most.
  std::array<double, kWindow> sorted{};
  for (int k = 0; k < count_; ++k) {
    const double v = lengths_m_[static_cast<std::size_t>(k)];
    int j = k;
    for (; j > 0 && sorted[static_cast<std::size_t>(j - 1)] > v; --j) {
      sorted[static_cast<std::size_t>(j)] = sorted[static_cast<std::size_t>(j - 1)];
    }
    sorted[static_cast<std::size_t>(j)] = v;
  }
  const double median = sorted[static_cast<std::size_t>(count_ / 2)];
  int agreeing = 0;
  for (int k = 0; k < count_; ++k) {
    if (std::fabs(sorted[static_cast<std::size_t>(k)] - median) <= kToleranceM) ++agreeing;
  }
  return agreeing >= kMinAgreeing ? median : -1.0;
}

void BarLengthTally::reset() {
  count_ = 0;
  next_ = 0;
}

}  // namespace fsw_app
