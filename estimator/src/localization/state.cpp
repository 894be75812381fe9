#include "estimator/localization/state.hpp"

#include "estimator/localization/so3.hpp"

namespace estimator::localization {

bool is_finite(const NominalState& x) {
  return x.p_world_body_m.allFinite() && x.v_world_body_mps.allFinite() &&
         x.q_world_body.coeffs().allFinite() && x.gyro_bias_radps.allFinite() &&
         x.accel_bias_mps2.allFinite();
}

void inject(const ErrorVector& dx, NominalState* x, Covariance* P) {
  const Eigen::Vector3d dtheta = dx.segment<3>(kAtt);
  x->p_world_body_m += dx.segment<3>(kPos);
  x->v_world_body_mps += dx.segment<3>(kVel);
  x->q_world_body = (quat_exp(dtheta) * x->q_world_body).normalized();
  x->gyro_bias_radps += dx.segment<3>(kGyroBias);
  x->accel_bias_mps2 += dx.segment<3>(kAccelBias);

  // G differs from I only in the attitude block, so G P G^T touches only the
  // attitude rows and columns: no 15 x 15 products.
  const Eigen::Matrix3d G = Eigen::Matrix3d::Identity() + 0.5 * skew(dtheta);
  P->middleRows<3>(kAtt) = G.lazyProduct(P->middleRows<3>(kAtt)).eval();
  P->middleCols<3>(kAtt) = P->middleCols<3>(kAtt).lazyProduct(G.transpose()).eval();
}

}  // namespace estimator::localization
