#include "estimator/localization/gates.hpp"

#include <cmath>
#include <limits>

namespace estimator::localization {
namespace {

// Regularised lower incomplete gamma function P(a, x) (Numerical Recipes'
// gser / gcf): the series converges fast below a + 1, the continued
// fraction above.
double gamma_p(double a, double x) {
  if (!(x > 0.0)) return 0.0;
  const double log_prefactor = -x + a * std::log(x) - std::lgamma(a);
  if (x < a + 1.0) {
    double term = 1.0 / a, sum = term;
    for (int n = 1; n < 300; ++n) {
      term *= x / (a + n);
      sum += term;
      if (std::fabs(term) < std::fabs(sum) * 1e-16) break;
    }
    return sum * std::exp(log_prefactor);
  }
  // Lentz's method for Q(a, x).
  const double tiny = 1e-300;
  double b = x + 1.0 - a, c = 1.0 / tiny, d = 1.0 / b, h = d;
  for (int n = 1; n < 300; ++n) {
    const double an = -n * (n - a);
    b += 2.0;
    d = an * d + b;
    if (std::fabs(d) < tiny) d = tiny;
    c = b + an / c;
    if (std::fabs(c) < tiny) c = tiny;
    d = 1.0 / d;
    const double delta = d * c;
    h *= delta;
    if (std::fabs(delta - 1.0) < 1e-16) break;
  }
  return 1.0 - std::exp(log_prefactor) * h;
}

}  // namespace

double chi_square_cdf(int dof, double x) {
  return gamma_p(0.5 * dof, 0.5 * x);
}

double chi_square_quantile(int dof, double probability) {
  if (dof < 1 || !(probability > 0.0 && probability < 1.0)) {
    return std::numeric_limits<double>::quiet_NaN();
  }
  // The quantile is below k + 40 sqrt(2k) + 100 for any p < 1 - 1e-9.
  double lo = 0.0, hi = dof + 40.0 * std::sqrt(2.0 * dof) + 100.0;
  for (int i = 0; i < 100; ++i) {
    const double mid = 0.5 * (lo + hi);
    (chi_square_cdf(dof, mid) < probability ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

ChiSquareGate::ChiSquareGate(double probability) : probability_(probability) {
  threshold_[0] = 0.0;
  for (int k = 1; k <= kMaxGateDof; ++k) {
    threshold_[static_cast<std::size_t>(k)] = chi_square_quantile(k, probability);
  }
}

double ChiSquareGate::threshold(int dof) const {
  if (dof < 1 || dof > kMaxGateDof) return -1.0;
  return threshold_[static_cast<std::size_t>(dof)];
}

std::uint32_t FilterCounters::rejected(MeasurementKind k) const {
  std::uint32_t n = 0;
  for (int s = 0; s < kNumUpdateStatus; ++s) {
    if (is_rejection(static_cast<UpdateStatus>(s))) {
      n += updates[static_cast<std::size_t>(k)][static_cast<std::size_t>(s)];
    }
  }
  return n;
}

}  // namespace estimator::localization
