#pragma once
// The checks the tests run after every step: the state finite with a unit
// quaternion, the covariance finite, symmetric and positive definite.
#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <cmath>

#include "estimator/localization/state.hpp"
#include "estimator/localization/status.hpp"

namespace estimator::localization {

// A covariance of any fixed size: finite, symmetric to within 1e-9 of its
// largest variance, every variance positive, and a Cholesky factor exists.
template <int N>
Health check_covariance(const Eigen::Matrix<double, N, N>& P) {
  if (!P.allFinite()) return Health::kNotFinite;
  const double scale = P.diagonal().cwiseAbs().maxCoeff();
  if ((P - P.transpose()).cwiseAbs().maxCoeff() > 1e-9 * scale) return Health::kNotSymmetric;
  if (!(P.diagonal().minCoeff() > 0.0)) return Health::kNotPositiveDefinite;
  Eigen::LLT<Eigen::Matrix<double, N, N>> llt(P);
  if (llt.info() != Eigen::Success) return Health::kNotPositiveDefinite;
  return Health::kOk;
}

// The whole filter state: finite, |q| = 1 within 1e-9, and the covariance.
Health check_filter(const NominalState& x, const Covariance& P);

// P = (P + P^T) / 2: rounding in the updates leaves a last-digit asymmetry
// that would otherwise grow.
void symmetrize(Covariance* P);

}  // namespace estimator::localization
