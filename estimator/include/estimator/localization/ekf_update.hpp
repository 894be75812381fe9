#pragma once
// The Kalman update of the error state, one block of D rows at a time, in
// Joseph form: P+ = (I - K H) P (I - K H)^T + K R K^T, which stays symmetric
// positive semi-definite for any gain, so rounding in K cannot make P
// indefinite (the short form P - K S K^T can).
//
// Blocks of one measurement are applied in turn to a working copy of P and
// an accumulated correction dx, each block's residual taken against the
// correction so far (r - H dx): with every H evaluated at the same prior and
// independent noise per block, this equals the stacked (batch) update
// exactly, and the sum of the blocks' NIS equals the stacked NIS, which is
// what the chi-square gate judges. Fixed sizes only: D = 2, 3 or 6.
#include <Eigen/Core>

#include "estimator/localization/state.hpp"
#include "estimator/localization/status.hpp"

namespace estimator::localization {

// The outcome of one measurement update.
struct UpdateResult {
  UpdateStatus status = UpdateStatus::kRejectedInvalid;
  double nis = 0.0;        // of what the gate judged
  int dof = 0;             // its dimension
  int features_used = 0;   // handrail: features in the update
  int features_gated = 0;  // handrail: features dropped by their own gate
};

template <int D>
struct BlockObservation {
  Eigen::Matrix<double, D, 1> r = Eigen::Matrix<double, D, 1>::Zero();  // z - h(x)
  Eigen::Matrix<double, D, kErrorDim> H = Eigen::Matrix<double, D, kErrorDim>::Zero();
  Eigen::Matrix<double, D, D> R = Eigen::Matrix<double, D, D>::Identity();
};

// The block's NIS r^T (H P H^T + R)^-1 r against P, without updating (the
// per-feature gate). False when H P H^T + R is not positive definite.
template <int D>
bool block_nis(const BlockObservation<D>& m, const Covariance& P, double* nis);

// One block into (P, dx): r_eff = r - H dx, S = H P H^T + R,
// K = P H^T S^-1, dx += K r_eff, P = Joseph. *nis receives r_eff^T S^-1
// r_eff. False (P and dx untouched) when S is not positive definite.
template <int D>
bool joseph_update(const BlockObservation<D>& m, Covariance* P, ErrorVector* dx, double* nis);

// Folds a finished update (correction dx, Joseph-updated covariance P_post)
// into the state; false, with x and P untouched, if the result is not finite
// or not positive definite (it cannot be in exact arithmetic).
bool commit_update(const ErrorVector& dx, const Covariance& P_post, NominalState* x, Covariance* P);

extern template bool block_nis<2>(const BlockObservation<2>&, const Covariance&, double*);
extern template bool block_nis<3>(const BlockObservation<3>&, const Covariance&, double*);
extern template bool block_nis<6>(const BlockObservation<6>&, const Covariance&, double*);
extern template bool joseph_update<2>(const BlockObservation<2>&, Covariance*, ErrorVector*,
                                      double*);
extern template bool joseph_update<3>(const BlockObservation<3>&, Covariance*, ErrorVector*,
                                      double*);
extern template bool joseph_update<6>(const BlockObservation<6>&, Covariance*, ErrorVector*,
                                      double*);

}  // namespace estimator::localization
