#include "estimator/localization/ekf_update.hpp"

#include <Eigen/Cholesky>

#include "estimator/localization/covariance_check.hpp"

namespace estimator::localization {

// Products here are small and fixed-size: lazyProduct() keeps them
// coefficient-based (Eigen sends anything with rows + cols + depth >= 20 down
// its blocked GEMM path, whose packing costs more than the arithmetic at
// these sizes); every inner product is evaluated once into a temporary.

template <int D>
bool block_nis(const BlockObservation<D>& m, const Covariance& P, double* nis) {
  using MatD = Eigen::Matrix<double, D, D>;
  const Eigen::Matrix<double, kErrorDim, D> PHt = P.lazyProduct(m.H.transpose());
  const MatD S = m.H.lazyProduct(PHt) + m.R;
  const Eigen::LLT<MatD> llt(S);
  if (llt.info() != Eigen::Success) return false;
  *nis = m.r.dot(llt.solve(m.r));
  return std::isfinite(*nis);
}

template <int D>
bool joseph_update(const BlockObservation<D>& m, Covariance* P, ErrorVector* dx, double* nis) {
  using MatD = Eigen::Matrix<double, D, D>;
  using MatND = Eigen::Matrix<double, kErrorDim, D>;
  const Eigen::Matrix<double, D, 1> r = m.r - m.H.lazyProduct(*dx);
  const MatND PHt = P->lazyProduct(m.H.transpose());
  const MatD S = m.H.lazyProduct(PHt) + m.R;
  const Eigen::LLT<MatD> llt(S);
  if (llt.info() != Eigen::Success) return false;
  // K = P H^T S^-1 (S is D x D, D <= 6: its inverse from the factor is cheap
  // and better conditioned than solving 21 right-hand sides one by one).
  const MatD S_inv = llt.solve(MatD::Identity());
  const MatND K = PHt.lazyProduct(S_inv);
  const double block = r.dot(S_inv.lazyProduct(r));
  if (!std::isfinite(block) || !K.allFinite()) return false;
  *nis = block;
  *dx += K.lazyProduct(r);
  // Joseph form with A = I - K H, using the block's low rank: A P =
  // P - K (H P) and (A P) A^T = A P - ((A P) H^T) K^T, 3 * 21 * 21 * D
  // multiplications instead of two dense 21 x 21 products.
  const Covariance AP = *P - K.lazyProduct(PHt.transpose());
  const MatND APHt = AP.lazyProduct(m.H.transpose());
  const MatND KR = K.lazyProduct(m.R);
  *P = AP - APHt.lazyProduct(K.transpose()) + KR.lazyProduct(K.transpose());
  symmetrize(P);
  return true;
}

bool commit_update(const ErrorVector& dx, const Covariance& P_post, NominalState* x,
                   Covariance* P) {
  if (!dx.allFinite()) return false;
  NominalState x_new = *x;
  Covariance P_new = P_post;
  inject(dx, &x_new, &P_new);
  symmetrize(&P_new);
  if (check_filter(x_new, P_new) != Health::kOk) return false;
  *x = x_new;
  *P = P_new;
  return true;
}

template bool block_nis<2>(const BlockObservation<2>&, const Covariance&, double*);
template bool block_nis<3>(const BlockObservation<3>&, const Covariance&, double*);
template bool block_nis<6>(const BlockObservation<6>&, const Covariance&, double*);
template bool joseph_update<2>(const BlockObservation<2>&, Covariance*, ErrorVector*, double*);
template bool joseph_update<3>(const BlockObservation<3>&, Covariance*, ErrorVector*, double*);
template bool joseph_update<6>(const BlockObservation<6>&, Covariance*, ErrorVector*, double*);

}  // namespace estimator::localization
