#include "estimator/localization/config.hpp"

#include <cmath>

namespace estimator::localization {
namespace {

bool in(double v, double lo, double hi) {
  return std::isfinite(v) && v >= lo && v <= hi;
}
bool positive_below(double v, double hi) {
  return std::isfinite(v) && v > 0.0 && v <= hi;
}

}  // namespace

Eigen::Isometry3d default_T_body_cam() {
  Eigen::Matrix3d R;
  // Columns: the camera's x (right), y (down), z (forward) in the body frame.
  R.col(0) = Eigen::Vector3d(0, 1, 0);
  R.col(1) = Eigen::Vector3d(0, 0, -1);
  R.col(2) = Eigen::Vector3d(-1, 0, 0);
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = R;
  T.translation() = Eigen::Vector3d(-0.16, 0.0, 0.06);
  return T;
}

const char* validate(const LocalizationConfig& c) {
  if (!positive_below(c.imu.gyro_noise_radps_rthz, 1.0)) return "imu.gyro_noise_radps_rthz";
  if (!positive_below(c.imu.accel_noise_mps2_rthz, 10.0)) return "imu.accel_noise_mps2_rthz";
  if (!positive_below(c.imu.gyro_bias_rw_radps2_rthz, 1.0)) return "imu.gyro_bias_rw_radps2_rthz";
  if (!positive_below(c.imu.accel_bias_rw_mps3_rthz, 10.0)) return "imu.accel_bias_rw_mps3_rthz";
  if (!in(c.imu_rate_hz, 10.0, 1000.0)) return "imu_rate_hz";
  if (!in(c.max_imu_step_s, 1.0 / c.imu_rate_hz, 0.5)) return "max_imu_step_s";
  if (!in(c.max_imu_gap_s, c.max_imu_step_s, 10.0) ||
      c.max_imu_gap_s * c.imu_rate_hz > kMaxGapSubsteps)
    return "max_imu_gap_s";
  if (!positive_below(c.gap_accel_sigma_mps2_rthz, 10.0)) return "gap_accel_sigma_mps2_rthz";
  if (!positive_below(c.gap_rate_sigma_radps_rthz, 10.0)) return "gap_rate_sigma_radps_rthz";
  if (!positive_below(c.lost_position_sigma_m, 100.0)) return "lost_position_sigma_m";
  if (!positive_below(c.lost_attitude_sigma_rad, 3.2)) return "lost_attitude_sigma_rad";
  if (!positive_below(c.lost_velocity_sigma_mps, 10.0)) return "lost_velocity_sigma_mps";
  if (!positive_below(c.max_rate_radps, 100.0)) return "max_rate_radps";
  if (!positive_below(c.max_accel_mps2, 1000.0)) return "max_accel_mps2";
  if (!c.g_world_mps2.allFinite() || c.g_world_mps2.norm() > 20.0) return "g_world_mps2";
  if (!positive_below(c.init_velocity_sigma_mps, 10.0)) return "init_velocity_sigma_mps";
  if (!positive_below(c.init_gyro_bias_sigma_radps, 1.0)) return "init_gyro_bias_sigma_radps";
  if (!positive_below(c.init_accel_bias_sigma_mps2, 10.0)) return "init_accel_bias_sigma_mps2";
  if (!c.init_gyro_bias_radps.allFinite() || c.init_gyro_bias_radps.norm() > 1.0)
    return "init_gyro_bias_radps";
  if (!c.init_accel_bias_mps2.allFinite() || c.init_accel_bias_mps2.norm() > 10.0)
    return "init_accel_bias_mps2";
  if (!in(c.max_future_s, 0.0, 0.5)) return "max_future_s";
  if (!in(c.gate_probability, 0.5, 1.0 - 1e-9)) return "gate_probability";
  if (c.relocalize_after < 1 || c.relocalize_after > 100) return "relocalize_after";
  if (c.reinitialize_after < 1 || c.reinitialize_after > 100) return "reinitialize_after";
  if (!positive_below(c.relocalize_agreement_m, 10.0)) return "relocalize_agreement_m";
  if (!positive_below(c.relocalize_agreement_rad, 3.2)) return "relocalize_agreement_rad";
  const Eigen::Matrix3d& R = c.T_body_cam.linear();
  if (!c.T_body_cam.matrix().allFinite() ||
      (R.transpose() * R - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() > 1e-6 ||
      R.determinant() < 0.0 || c.T_body_cam.translation().norm() > 2.0)
    return "T_body_cam";
  if (!positive_below(c.bar_feature_sigma_m, 1.0)) return "bar_feature_sigma_m";
  if (!positive_below(c.wall_feature_sigma_m, 1.0)) return "wall_feature_sigma_m";
  if (c.max_bar_features < 0 || c.max_bar_features > kMaxUsedBarFeatures) return "max_bar_features";
  if (c.max_wall_features < 0 || c.max_wall_features > kMaxUsedWallFeatures)
    return "max_wall_features";
  if (c.min_features < 1 || c.min_features > c.max_bar_features + c.max_wall_features)
    return "min_features";
  if (c.map_init_sightings < 1 || c.map_init_sightings > 100) return "map_init_sightings";
  if (!positive_below(c.map_consistency_m, 1.0)) return "map_consistency_m";
  if (!positive_below(c.map_consistency_rad, 3.2)) return "map_consistency_rad";
  if (!positive_below(c.map_init_max_position_sigma_m, 100.0))
    return "map_init_max_position_sigma_m";
  if (c.map_reset_after_rejections < 1 || c.map_reset_after_rejections > 10000)
    return "map_reset_after_rejections";
  if (!positive_below(c.map_sighting_position_sigma_m, 1.0)) return "map_sighting_position_sigma_m";
  if (!positive_below(c.map_sighting_attitude_sigma_rad, 1.0))
    return "map_sighting_attitude_sigma_rad";
  if (!in(c.handrail_hold_s, 0.0, 60.0)) return "handrail_hold_s";
  return nullptr;
}

}  // namespace estimator::localization
