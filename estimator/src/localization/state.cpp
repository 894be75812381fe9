#include "estimator/localization/state.hpp"

#include "estimator/localization/so3.hpp"

namespace estimator::localization {

bool is_finite(const NominalState& x) {
  return x.p_world_body_m.allFinite() && x.v_world_body_mps.allFinite() &&
         x.q_world_body.coeffs().allFinite() && x.gyro_bias_radps.allFinite() &&
         x.accel_bias_mps2.allFinite() && x.p_world_handrail_m.allFinite() &&
         x.q_world_handrail.coeffs().allFinite();
}

void inject(const ErrorVector& dx, NominalState* x, Covariance* P) {
  x->p_world_body_m += dx.segment<3>(kPos);
  x->v_world_body_mps += dx.segment<3>(kVel);
  x->q_world_body = (quat_exp(dx.segment<3>(kAtt)) * x->q_world_body).normalized();
  x->gyro_bias_radps += dx.segment<3>(kGyroBias);
  x->accel_bias_mps2 += dx.segment<3>(kAccelBias);
  x->p_world_handrail_m += dx.segment<3>(kMapPos);
  x->q_world_handrail = (quat_exp(dx.segment<3>(kMapAtt)) * x->q_world_handrail).normalized();

  // G differs from I only in the two attitude blocks, so G P G^T touches
  // only their rows and columns: no full-size products.
  for (int block : {kAtt, kMapAtt}) {
    const Eigen::Matrix3d G = Eigen::Matrix3d::Identity() + 0.5 * skew(dx.segment<3>(block));
    P->middleRows<3>(block) = G.lazyProduct(P->middleRows<3>(block)).eval();
    P->middleCols<3>(block) = P->middleCols<3>(block).lazyProduct(G.transpose()).eval();
  }
}

}  // namespace estimator::localization
