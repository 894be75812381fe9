#include "estimator/localization/covariance_check.hpp"

namespace estimator::localization {

Health check_filter(const NominalState& x, const Covariance& P) {
  if (!is_finite(x)) return Health::kStateNotFinite;
  if (std::fabs(x.q_world_body.norm() - 1.0) > 1e-9) return Health::kQuaternionNotUnit;
  return check_covariance(P);
}

void symmetrize(Covariance* P) {
  *P = (0.5 * (*P + P->transpose())).eval();
}

}  // namespace estimator::localization
