#pragma once
// The chi-square gate on every update, and the counts of what happened to
// every input, by kind and outcome.
#include <array>
#include <cstdint>

#include "estimator/localization/config.hpp"
#include "estimator/localization/status.hpp"

namespace estimator::localization {

// The largest measurement dimension gated: a handrail update's stacked
// residual (3 per feature) or one 6-D pose.
constexpr int kMaxGateDof = 3 * kMaxUsedFeatures;

// P(k/2, x/2), the chi-square CDF with k degrees of freedom at x (series or
// continued fraction, at most 300 terms).
double chi_square_cdf(int dof, double x);
// Its inverse at probability p in (0, 1), by bisection (100 halvings).
double chi_square_quantile(int dof, double probability);

// Accepts a normalised innovation squared (NIS = r^T S^-1 r) when it is
// below the chi-square quantile for its dimension: the gate is per
// measurement dimension, so a 2-D NE residual and a 36-D BE stack are judged
// at the same probability. The table is filled once, at construction.
class ChiSquareGate {
 public:
  explicit ChiSquareGate(double probability = 0.999);
  double threshold(int dof) const;  // -1 outside 1..kMaxGateDof: nothing passes
  bool passes(double nis, int dof) const { return nis >= 0.0 && nis <= threshold(dof); }
  double probability() const { return probability_; }

 private:
  double probability_;
  std::array<double, kMaxGateDof + 1> threshold_{};
};

// What happened to every input: per IMU status, and per measurement kind
// and update status; plus the finer points of the handrail and the history.
struct FilterCounters {
  std::array<std::uint32_t, kNumImuStatus> imu{};
  std::array<std::array<std::uint32_t, kNumUpdateStatus>, kNumMeasurementKinds> updates{};
  std::uint32_t features_gated = 0;     // single features dropped by their own gate
  std::uint32_t replay_rejections = 0;  // stored updates failing the gate when re-applied
  std::uint32_t store_evictions = 0;    // stored updates pushed out by newer ones
  std::uint32_t map_restarts = 0;       // an inconsistent sighting restarted the map
  std::uint32_t map_resets = 0;         // the map dropped (rejections, relocalisation)
  std::uint32_t map_line_replaced = 0;  // a line map dropped for a sighting with an end
  std::uint32_t reinitializations = 0;  // started again from a GP pose (divergence rule)

  std::uint32_t count(ImuStatus s) const { return imu[static_cast<std::size_t>(s)]; }
  std::uint32_t count(MeasurementKind k, UpdateStatus s) const {
    return updates[static_cast<std::size_t>(k)][static_cast<std::size_t>(s)];
  }
  // Every rejection of one kind, whatever the reason.
  std::uint32_t rejected(MeasurementKind k) const;
  void note(ImuStatus s) { ++imu[static_cast<std::size_t>(s)]; }
  void note(MeasurementKind k, UpdateStatus s) {
    ++updates[static_cast<std::size_t>(k)][static_cast<std::size_t>(s)];
  }
};

}  // namespace estimator::localization
