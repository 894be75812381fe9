#include "estimator/localization/pose_update.hpp"

#include <cmath>

#include "estimator/localization/covariance_check.hpp"
#include "estimator/localization/so3.hpp"

namespace estimator::localization {
namespace {
constexpr double kPi = 3.14159265358979323846;
}  // namespace

UpdateStatus check_gp_pose(const GpPose& g) {
  if (!g.p_world_body_m.allFinite() || !g.q_world_body.coeffs().allFinite() || !g.cov.allFinite()) {
    return UpdateStatus::kRejectedNotFinite;
  }
  if (std::fabs(g.q_world_body.norm() - 1.0) > 1e-3) return UpdateStatus::kRejectedInvalid;
  if (check_covariance(g.cov) != Health::kOk) return UpdateStatus::kRejectedInvalid;
  for (int i = 0; i < 3; ++i) {
    if (g.cov(i, i) > 100.0 * 100.0) return UpdateStatus::kRejectedInvalid;
    if (g.cov(3 + i, 3 + i) > kPi * kPi) return UpdateStatus::kRejectedInvalid;
  }
  return UpdateStatus::kAccepted;
}

BlockObservation<6> gp_observation(const GpPose& g, const NominalState& x) {
  BlockObservation<6> m;
  m.r.head<3>() = g.p_world_body_m - x.p_world_body_m;
  m.r.tail<3>() = quat_log(g.q_world_body.normalized() * x.q_world_body.conjugate());
  m.H.block<3, 3>(0, kPos).setIdentity();
  m.H.block<3, 3>(3, kAtt).setIdentity();
  m.R = g.cov;
  return m;
}

UpdateResult gp_update(const ChiSquareGate& gate, const GpPose& g, NominalState* x, Covariance* P) {
  UpdateResult res;
  res.dof = 6;
  const BlockObservation<6> m = gp_observation(g, *x);
  Covariance P_work = *P;
  ErrorVector dx = ErrorVector::Zero();
  if (!joseph_update(m, &P_work, &dx, &res.nis)) {
    res.status = UpdateStatus::kRejectedNumerical;
    return res;
  }
  if (!gate.passes(res.nis, res.dof)) {
    res.status = UpdateStatus::kRejectedGate;
    return res;
  }
  res.status =
      commit_update(dx, P_work, x, P) ? UpdateStatus::kAccepted : UpdateStatus::kRejectedNumerical;
  return res;
}

}  // namespace estimator::localization
