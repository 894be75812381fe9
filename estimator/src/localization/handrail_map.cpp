#include "estimator/localization/handrail_map.hpp"

#include <cmath>

namespace estimator::localization {

Eigen::Matrix3d flip_axis(const Eigen::Matrix3d& R_x_handrail) {
  Eigen::Matrix3d R = R_x_handrail;
  R.col(1) = -R.col(1);
  R.col(2) = -R.col(2);
  return R;
}

UpdateStatus check_survey(const HandrailMap& survey) {
  const Eigen::Matrix3d& R = survey.T_world_handrail.linear();
  const Eigen::Vector3d& p = survey.T_world_handrail.translation();
  if (!R.allFinite() || !p.allFinite() || !std::isfinite(survey.position_sigma_m) ||
      !std::isfinite(survey.attitude_sigma_rad)) {
    return UpdateStatus::kRejectedNotFinite;
  }
  const bool rotation =
      (R.transpose() * R - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() <= 1e-6 &&
      R.determinant() > 0.0;
  const bool in_range = p.norm() <= 1000.0 && survey.position_sigma_m >= 0.0 &&
                        survey.position_sigma_m <= 1.0 && survey.attitude_sigma_rad >= 0.0 &&
                        survey.attitude_sigma_rad <= 1.0;
  return rotation && in_range ? UpdateStatus::kAccepted : UpdateStatus::kRejectedInvalid;
}

void HandrailMapBuilder::set_survey(const HandrailMap& survey) {
  reset();
  map_ = survey;
  map_.valid = map_.surveyed = true;
}

void HandrailMapBuilder::reset() {
  *this = HandrailMapBuilder();
}

void HandrailMapBuilder::start(const Eigen::Isometry3d& T, bool along_known) {
  const Eigen::Quaterniond q(T.linear());
  count_ = 1;
  counting_along_known_ = along_known;
  first_p_ = T.translation();
  sum_p_ = T.translation();
  sum_q_ = q.coeffs();
  mean_p_ = sum_p_;
  mean_q_ = q;
}

UpdateStatus HandrailMapBuilder::add_sighting(const LocalizationConfig& cfg,
                                              const Eigen::Isometry3d& T_world_handrail,
                                              bool along_known, bool* restarted) {
  *restarted = false;
  if (map_.valid) return UpdateStatus::kMapInitialized;
  if (count_ > 0 && counting_along_known_ && !along_known) return UpdateStatus::kNoMap;
  Eigen::Isometry3d T = T_world_handrail;
  if (count_ > 0 && !counting_along_known_ && along_known) {
    start(T, true);  // an end seen: a map placed along the bar, not a line
  } else if (count_ == 0) {
    start(T, along_known);
  } else {
    // The same bar with its axis reversed is the same sighting.
    if (T.linear().col(2).dot(mean_q_.toRotationMatrix().col(2)) < 0.0) {
      T.linear() = flip_axis(T.linear());
    }
    Eigen::Quaterniond q(T.linear());
    if (q.coeffs().dot(mean_q_.coeffs()) < 0.0) q.coeffs() = -q.coeffs();
    // No end seen: the origin is only somewhere on the bar. Slid along the
    // mean axis onto the plane across the first origin, so that the test
    // and the mean are across the bar only (a restart keeps its own).
    Eigen::Vector3d p = T.translation();
    if (!along_known) {
      const Eigen::Vector3d axis = mean_q_ * Eigen::Vector3d::UnitZ();
      p -= axis * axis.dot(p - first_p_);
    }
    const bool agrees = (p - mean_p_).norm() <= cfg.map_consistency_m &&
                        q.angularDistance(mean_q_) <= cfg.map_consistency_rad;
    T.translation() = p;
    if (!agrees) {
      start(T_world_handrail, along_known);
      *restarted = true;
    } else {
      ++count_;
      sum_p_ += T.translation();
      sum_q_ += q.coeffs();
      mean_p_ = sum_p_ / count_;
      // The normalised sum of same-hemisphere quaternions: the rotation mean
      // to second order in the spread, which the consistency test keeps small.
      mean_q_.coeffs() = sum_q_.normalized();
    }
  }
  if (count_ < cfg.map_init_sightings) return UpdateStatus::kMapSighting;
  map_.valid = true;
  map_.along_known = counting_along_known_;
  map_.T_world_handrail.setIdentity();
  map_.T_world_handrail.linear() = mean_q_.toRotationMatrix();
  map_.T_world_handrail.translation() = mean_p_;
  return UpdateStatus::kMapInitialized;
}

}  // namespace estimator::localization
