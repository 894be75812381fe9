#include "estimator/localization/handrail_update.hpp"

#include <algorithm>
#include <cmath>

#include "estimator/localization/so3.hpp"

namespace estimator::localization {
namespace {

bool usable_state(HandrailState s) {
  return s == HandrailState::kBothEnds || s == HandrailState::kOneEnd || s == HandrailState::kNoEnd;
}

// Farthest-point sampling of up to `want` of the features of one kind into
// out, starting at out->num_features.
void thin(const HandrailMeasurement& m, FeatureKind kind, int want, SelectedFeatures* out) {
  std::array<int, kMaxInputFeatures> idx{};
  std::array<double, kMaxInputFeatures> d2{};  // to the nearest chosen one
  int n = 0;
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (int k = 0; k < m.num_features; ++k) {
    const HandrailFeature& f = m.features[static_cast<std::size_t>(k)];
    if (f.kind != kind) continue;
    idx[static_cast<std::size_t>(n++)] = k;
    centroid += f.p_handrail_m;
  }
  if (n == 0 || want <= 0) return;
  centroid /= n;
  const auto at = [&](int i) -> const HandrailFeature& {
    return m.features[static_cast<std::size_t>(idx[static_cast<std::size_t>(i)])];
  };
  for (int i = 0; i < n; ++i) {
    d2[static_cast<std::size_t>(i)] = (at(i).p_handrail_m - centroid).squaredNorm();
  }
  for (int chosen = 0; chosen < want && chosen < n; ++chosen) {
    int best = -1;
    double best_d2 = -1.0;
    for (int i = 0; i < n; ++i) {
      if (d2[static_cast<std::size_t>(i)] > best_d2) {
        best_d2 = d2[static_cast<std::size_t>(i)];
        best = i;
      }
    }
    if (best < 0) break;  // every feature taken (a taken one has d2 = -1)
    const HandrailFeature& f = at(best);
    out->features[static_cast<std::size_t>(out->num_features++)] = f;
    d2[static_cast<std::size_t>(best)] = -1.0;
    for (int i = 0; i < n; ++i) {
      double& d = d2[static_cast<std::size_t>(i)];
      if (d < 0.0) continue;
      // After the first pick distances are to the chosen set, not the centroid.
      const double di = (at(i).p_handrail_m - f.p_handrail_m).squaredNorm();
      d = chosen == 0 ? di : std::fmin(d, di);
    }
  }
}

}  // namespace

UpdateStatus check_handrail_measurement(const HandrailMeasurement& m) {
  if (!m.T_cam_handrail.matrix().allFinite()) return UpdateStatus::kRejectedNotFinite;
  if (m.num_features < 0 || m.num_features > kMaxInputFeatures) {
    return UpdateStatus::kRejectedInvalid;
  }
  for (int k = 0; k < m.num_features; ++k) {
    const HandrailFeature& f = m.features[static_cast<std::size_t>(k)];
    if (!f.p_cam_m.allFinite() || !f.p_handrail_m.allFinite()) {
      return UpdateStatus::kRejectedNotFinite;
    }
    if (f.kind != FeatureKind::kBar && f.kind != FeatureKind::kWall) {
      return UpdateStatus::kRejectedInvalid;
    }
    if (f.p_cam_m.norm() > 20.0 || f.p_handrail_m.norm() > 20.0) {
      return UpdateStatus::kRejectedInvalid;
    }
  }
  if (!usable_state(m.state)) return UpdateStatus::kRejectedInvalid;
  const Eigen::Matrix3d R = m.T_cam_handrail.linear();
  if ((R.transpose() * R - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() > 1e-4 ||
      R.determinant() < 0.0 || m.T_cam_handrail.translation().norm() > 20.0 ||
      (m.T_cam_handrail.matrix().row(3) - Eigen::RowVector4d(0, 0, 0, 1)).cwiseAbs().maxCoeff() >
          0.0) {
    return UpdateStatus::kRejectedInvalid;
  }
  return UpdateStatus::kAccepted;
}

void select_features(const HandrailMeasurement& m, int max_bar, int max_wall,
                     SelectedFeatures* out) {
  out->state = m.state;
  out->R_cam_handrail = m.T_cam_handrail.linear();
  out->num_features = 0;
  thin(m, FeatureKind::kBar, std::min(max_bar, kMaxUsedBarFeatures), out);
  thin(m, FeatureKind::kWall, std::min(max_wall, kMaxUsedWallFeatures), out);
}

void align_with_map(const NominalState& x, const Eigen::Isometry3d& T_body_cam,
                    SelectedFeatures* s) {
  const Eigen::Matrix3d R_world_cam = x.q_world_body.toRotationMatrix() * T_body_cam.linear();
  const Eigen::Vector3d axis_world = R_world_cam * s->R_cam_handrail.col(2);
  if (axis_world.dot(x.q_world_handrail * Eigen::Vector3d::UnitZ()) >= 0.0) return;
  s->R_cam_handrail = flip_axis(s->R_cam_handrail);
  for (int k = 0; k < s->num_features; ++k) {
    Eigen::Vector3d& p = s->features[static_cast<std::size_t>(k)].p_handrail_m;
    p.y() = -p.y();
    p.z() = -p.z();
  }
}

FeatureContext feature_context(const NominalState& x, const Eigen::Isometry3d& T_body_cam) {
  FeatureContext c;
  const Eigen::Matrix3d R_world_body = x.q_world_body.toRotationMatrix();
  c.R_cam_world = (R_world_body * T_body_cam.linear()).transpose();  // eq. 7
  c.lever_world_m = R_world_body * T_body_cam.translation();         // R_WB ^B p_C
  c.p_world_cam_m = x.p_world_body_m + c.lever_world_m;              // eq. 7
  c.R_world_handrail = x.q_world_handrail.toRotationMatrix();
  c.p_world_handrail_m = x.p_world_handrail_m;
  return c;
}

BlockObservation<3> feature_observation(const FeatureContext& c, const HandrailFeature& f,
                                        double sigma_m) {
  BlockObservation<3> m;
  const Eigen::Vector3d lever_map_world_m = c.R_world_handrail * f.p_handrail_m;
  const Eigen::Vector3d p_world_feature = c.p_world_handrail_m + lever_map_world_m;
  const Eigen::Vector3d z_hat = c.R_cam_world * (p_world_feature - c.p_world_cam_m);  // eq. 6
  m.r = f.p_cam_m - z_hat;                                                            // eq. 9
  // Eq. 10 in the camera's error, then into the filter's error (state.hpp).
  m.H.block<3, 3>(0, kPos) = -c.R_cam_world;
  m.H.block<3, 3>(0, kAtt) = skew(z_hat) * c.R_cam_world + c.R_cam_world * skew(c.lever_world_m);
  // The map's error moves the predicted point: dp_map in full, dth_map by
  // its lever arm from the handrail's origin (eq. 8 perturbed).
  m.H.block<3, 3>(0, kMapPos) = c.R_cam_world;
  m.H.block<3, 3>(0, kMapAtt) = -c.R_cam_world * skew(lever_map_world_m);
  m.R = sigma_m * sigma_m * Eigen::Matrix3d::Identity();
  return m;
}

BlockObservation<2> feature_observation_no_end(const FeatureContext& c, const HandrailFeature& f,
                                               const Eigen::Matrix3d& R_cam_handrail,
                                               double sigma_m, bool reanchor_along_bar) {
  HandrailFeature g = f;
  if (reanchor_along_bar) {
    // Where the filter puts the measured point along the mapped bar.
    const Eigen::Vector3d p_world = c.R_cam_world.transpose() * f.p_cam_m + c.p_world_cam_m;
    g.p_handrail_m.z() = c.R_world_handrail.col(2).dot(p_world - c.p_world_handrail_m);
  }
  BlockObservation<3> m3 = feature_observation(c, g, sigma_m);
  if (reanchor_along_bar) {
    // The re-anchored feature follows the state along the bar, so the
    // prediction no longer depends on the state's along-bar component: the
    // Jacobian loses it too, H = R_CW (I - a a^T) R_WC H with a the mapped
    // axis (to first order in the residual). Without this the angle between
    // the detected and mapped axes would let eq. 13 "observe" the position
    // along the bar, and pin it, from a residual that holds nothing of it.
    const Eigen::Vector3d a_cam = c.R_cam_world * c.R_world_handrail.col(2);
    const Eigen::Matrix<double, 1, kErrorDim> aH = a_cam.transpose().lazyProduct(m3.H);
    m3.H -= a_cam.lazyProduct(aH);
  }
  // [I2 0] R_HC: the detected frame's x and y axes, in camera coordinates.
  const Eigen::Matrix<double, 2, 3> Pi_R_hc = R_cam_handrail.leftCols<2>().transpose();
  BlockObservation<2> m;
  m.r = Pi_R_hc * m3.r;             // eq. 12
  m.H = Pi_R_hc.lazyProduct(m3.H);  // eq. 13
  m.R = sigma_m * sigma_m * Eigen::Matrix2d::Identity();
  return m;
}

UpdateResult handrail_update(const LocalizationConfig& cfg, const ChiSquareGate& gate,
                             const SelectedFeatures& s, NominalState* x, Covariance* P) {
  UpdateResult res;
  const bool no_end = s.state == HandrailState::kNoEnd;
  const int dim = no_end ? 2 : 3;
  const FeatureContext c = feature_context(*x, cfg.T_body_cam);
  // The map's own uncertainty is in the state (state.hpp), not here.
  const auto sigma = [&](const HandrailFeature& f) {
    return f.kind == FeatureKind::kBar ? cfg.bar_feature_sigma_m : cfg.wall_feature_sigma_m;
  };
  // Each feature against the prior: a stray point is dropped before it can
  // pull the stack (the order of the features does not matter here).
  std::array<bool, kMaxUsedFeatures> keep{};
  for (int k = 0; k < s.num_features; ++k) {
    const HandrailFeature& f = s.features[static_cast<std::size_t>(k)];
    double nis = 0.0;
    const bool ok = no_end ? block_nis(feature_observation_no_end(c, f, s.R_cam_handrail, sigma(f),
                                                                  cfg.ne_reanchor_along_bar),
                                       *P, &nis)
                           : block_nis(feature_observation(c, f, sigma(f)), *P, &nis);
    if (!ok) {
      res.status = UpdateStatus::kRejectedNumerical;
      return res;
    }
    keep[static_cast<std::size_t>(k)] = gate.passes(nis, dim);
    if (keep[static_cast<std::size_t>(k)]) {
      ++res.features_used;
    } else {
      ++res.features_gated;
    }
  }
  if (res.features_used < cfg.min_features) {
    res.status = s.num_features >= cfg.min_features ? UpdateStatus::kRejectedGate
                                                    : UpdateStatus::kRejectedTooFewFeatures;
    return res;
  }
  // The kept features as one stacked measurement (exactly, see
  // ekf_update.hpp), on a working copy.
  Covariance P_work = *P;
  ErrorVector dx = ErrorVector::Zero();
  for (int k = 0; k < s.num_features; ++k) {
    if (!keep[static_cast<std::size_t>(k)]) continue;
    const HandrailFeature& f = s.features[static_cast<std::size_t>(k)];
    double nis = 0.0;
    const bool ok = no_end
                        ? joseph_update(feature_observation_no_end(c, f, s.R_cam_handrail, sigma(f),
                                                                   cfg.ne_reanchor_along_bar),
                                        &P_work, &dx, &nis)
                        : joseph_update(feature_observation(c, f, sigma(f)), &P_work, &dx, &nis);
    if (!ok) {
      res.status = UpdateStatus::kRejectedNumerical;
      return res;
    }
    res.nis += nis;
  }
  res.dof = dim * res.features_used;
  if (!gate.passes(res.nis, res.dof)) {
    res.status = UpdateStatus::kRejectedGate;
    return res;
  }
  res.status =
      commit_update(dx, P_work, x, P) ? UpdateStatus::kAccepted : UpdateStatus::kRejectedNumerical;
  return res;
}

}  // namespace estimator::localization
