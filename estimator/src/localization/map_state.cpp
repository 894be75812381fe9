#include "estimator/localization/map_state.hpp"

#include "estimator/localization/covariance_check.hpp"
#include "estimator/localization/so3.hpp"

namespace estimator::localization {
namespace {

void set_map_pose(const Eigen::Isometry3d& T_world_handrail, NominalState* x) {
  x->p_world_handrail_m = T_world_handrail.translation();
  x->q_world_handrail = Eigen::Quaterniond(T_world_handrail.linear()).normalized();
}

void set_map_variances(double position_var, double attitude_var, Covariance* P) {
  for (int i = 0; i < 3; ++i) {
    (*P)(kMapPos + i, kMapPos + i) += position_var;
    (*P)(kMapAtt + i, kMapAtt + i) += attitude_var;
  }
}

}  // namespace

void clear_map_block(Covariance* P) {
  P->middleRows<6>(kMapPos).setZero();
  P->middleCols<6>(kMapPos).setZero();
  set_map_variances(1.0, 1.0, P);
}

void attach_sighted_map(const LocalizationConfig& cfg, const Eigen::Isometry3d& T_world_handrail,
                        NominalState* x, Covariance* P) {
  set_map_pose(T_world_handrail, x);
  // J: the map's error from the robot's position and attitude error.
  Eigen::Matrix<double, 6, kErrorDim> J = Eigen::Matrix<double, 6, kErrorDim>::Zero();
  J.block<3, 3>(0, kPos).setIdentity();
  J.block<3, 3>(0, kAtt) = -skew(x->p_world_handrail_m - x->p_world_body_m);
  J.block<3, 3>(3, kAtt).setIdentity();
  clear_map_block(P);  // J has no map columns: J P must not see the old block
  const Eigen::Matrix<double, 6, kErrorDim> JP = J.lazyProduct(*P);
  const Eigen::Matrix<double, 6, 6> JPJt = JP.lazyProduct(J.transpose());
  P->middleRows<6>(kMapPos) = JP;
  P->middleCols<6>(kMapPos) = JP.transpose();
  P->block<6, 6>(kMapPos, kMapPos) = JPJt;
  set_map_variances(cfg.map_sighting_position_sigma_m * cfg.map_sighting_position_sigma_m,
                    cfg.map_sighting_attitude_sigma_rad * cfg.map_sighting_attitude_sigma_rad, P);
  symmetrize(P);
}

void attach_surveyed_map(const HandrailMap& survey, NominalState* x, Covariance* P) {
  set_map_pose(survey.T_world_handrail, x);
  P->middleRows<6>(kMapPos).setZero();
  P->middleCols<6>(kMapPos).setZero();
  // A survey of zero sigma is allowed (check_survey); a floor keeps the
  // covariance positive definite: 0.1 mm and 10 urad, far below any
  // measurement's.
  const double p_var = survey.position_sigma_m * survey.position_sigma_m + 1e-8;
  const double a_var = survey.attitude_sigma_rad * survey.attitude_sigma_rad + 1e-10;
  set_map_variances(p_var, a_var, P);
}

Eigen::Vector3d body_in_handrail(const NominalState& x) {
  return x.q_world_handrail.conjugate() * (x.p_world_body_m - x.p_world_handrail_m);
}

Eigen::Matrix3d body_in_handrail_cov(const NominalState& x, const Covariance& P) {
  const Eigen::Matrix3d R_handrail_world = x.q_world_handrail.conjugate().toRotationMatrix();
  Eigen::Matrix<double, 3, kErrorDim> J = Eigen::Matrix<double, 3, kErrorDim>::Zero();
  J.block<3, 3>(0, kPos) = R_handrail_world;
  J.block<3, 3>(0, kMapPos) = -R_handrail_world;
  J.block<3, 3>(0, kMapAtt) = R_handrail_world * skew(x.p_world_body_m - x.p_world_handrail_m);
  const Eigen::Matrix<double, 3, kErrorDim> JP = J.lazyProduct(P);
  return JP.lazyProduct(J.transpose());
}

}  // namespace estimator::localization
