#pragma once
// The update with a handrail measurement, as the paper's "Localization"
// section writes it (its notation: G world, B body, C_i camera of frame i,
// H handrail; z = measured feature, ^X p = position in frame X).
//
// Each feature j of frame i is a point measured in the camera frame, z_j,
// with its position in the handrail frame ^H p_j (eq. 8, second line: from
// the detected handrail pose; add_features() in measurements.hpp computes
// it). The handrail's world pose is the map's, held in the state
// (state.hpp, map_state.hpp).
//
//   eq. 7   camera pose from the body pose and the mount:
//           C_W = C_B R_BW,  ^G p_C = ^G p_B + R_WB ^B p_C    feature_context()
//   eq. 8   ^G p_j = ^G p_H + R_WH ^H p_j                     feature_observation()
//   eq. 6   z^_j = R_CW (^G p_j - ^G p_C)                     feature_observation()
//   eq. 9   r_j = z_j - z^_j ~ H_dtheta dtheta_C + H_p dp_C   feature_observation()
//   eq. 10  H_dtheta = [z^_j x],  H_p = -R_CW                 feature_observation()
//           mapped to the filter's error state by the chain rule of eq. 7
//           (dtheta_C = R_CW dtheta, dp_C = dp - [R_WB ^B p_C x] dtheta):
//           H = [-R_CW, 0, [z^_j x] R_CW + R_CW [R_WB ^B p_C x], 0, 0,
//                R_CW, -R_CW [R_WH ^H p_j x]]   (the last two: the map's error)
//   eq. 11  NE: the feature in the handrail frame, z'_j = ^H p_j  feature_observation_no_end()
//   eq. 12  r'_j = [I2 0] R_HC r_j                             feature_observation_no_end()
//   eq. 13  H'_j = [I2 0] R_HC H_j, R_HC from the detection     feature_observation_no_end()
//
// With an end in view (BE, OE) every feature gives the 3-D residual of eq. 9
// (noise sigma^2 I3); with no end (NE) the 2-D one of eq. 12 (sigma^2 I2: a
// rotation of isotropic noise), the along-bar component dropped because the
// detection cannot place the bar along its axis. One improvement, on by
// default (ne_reanchor_along_bar): before the NE residual the feature's
// along-bar coordinate is replaced by the predicted one, so the dropped
// component is zero and nothing of the detection's arbitrary along-bar
// origin (it can be tens of cm) leaks into the kept two through the small
// angle between the detected axis (R_HC) and the mapped one.
//
// The update: features thinned (select_features), each judged by its own
// chi-square gate against the prior (a stray point is dropped, counted),
// then all the kept ones applied as one stacked measurement by sequential
// Joseph blocks (ekf_update.hpp), the stacked NIS judged by the gate at the
// stack's dimension; a measurement with fewer than min_features left is
// rejected. A measurement off by a few cm fails every feature's gate.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>

#include "estimator/localization/config.hpp"
#include "estimator/localization/ekf_update.hpp"
#include "estimator/localization/gates.hpp"
#include "estimator/localization/handrail_map.hpp"
#include "estimator/localization/measurements.hpp"
#include "estimator/localization/state.hpp"

namespace estimator::localization {

// The features of one update after thinning, and what eq. 13 needs: what the
// filter keeps to re-apply the update on a re-propagation.
struct SelectedFeatures {
  HandrailState state = HandrailState::kNoHandrail;
  Eigen::Matrix3d R_cam_handrail = Eigen::Matrix3d::Identity();  // detected, for eq. 13
  std::array<HandrailFeature, kMaxUsedFeatures> features{};
  int num_features = 0;
};

// kAccepted for a usable measurement: state BE, OE or NE; everything finite;
// 0 <= num_features <= kMaxInputFeatures; T_cam_handrail a rotation (within
// 1e-4, what a float detector gives) and a translation within 20 m.
// Otherwise kRejectedNotFinite or kRejectedInvalid.
UpdateStatus check_handrail_measurement(const HandrailMeasurement& m);

// Thins the features in fixed memory: up to max_bar of the bar's and
// max_wall of the wall's, spread out by farthest-point sampling in the
// handrail frame (the first the farthest from its group's centroid, each
// next the farthest from those chosen), which keeps the long lever arms that
// pin the attitude. O(kMaxInputFeatures * kMaxUsedFeatures), deterministic.
void select_features(const HandrailMeasurement& m, int max_bar, int max_wall,
                     SelectedFeatures* out);

// When the detection's axis, seen from the filter's pose, points against the
// map's, turns the detection and its features' ^H p_j by pi about the wall
// normal (flip_axis): the same bar, the map's axis sign.
void align_with_map(const NominalState& x, const Eigen::Isometry3d& T_body_cam,
                    SelectedFeatures* s);

// What every feature of one update shares (eq. 7 and the map).
struct FeatureContext {
  Eigen::Matrix3d R_cam_world = Eigen::Matrix3d::Identity();
  Eigen::Vector3d p_world_cam_m = Eigen::Vector3d::Zero();
  Eigen::Vector3d lever_world_m = Eigen::Vector3d::Zero();  // R_WB ^B p_C
  Eigen::Matrix3d R_world_handrail = Eigen::Matrix3d::Identity();
  Eigen::Vector3d p_world_handrail_m = Eigen::Vector3d::Zero();
};
FeatureContext feature_context(const NominalState& x, const Eigen::Isometry3d& T_body_cam);

// Eqs. 6, 8, 9, 10 for one feature (BE, OE).
BlockObservation<3> feature_observation(const FeatureContext& c, const HandrailFeature& f,
                                        double sigma_m);

// Eqs. 11, 12, 13 for one feature (NE), R_cam_handrail the detected frame.
BlockObservation<2> feature_observation_no_end(const FeatureContext& c, const HandrailFeature& f,
                                               const Eigen::Matrix3d& R_cam_handrail,
                                               double sigma_m, bool reanchor_along_bar);

// The whole update at (x, P): per-feature gate, stacked Joseph update,
// stacked gate. x and P are untouched unless the result is kAccepted.
UpdateResult handrail_update(const LocalizationConfig& cfg, const ChiSquareGate& gate,
                             const SelectedFeatures& s, NominalState* x, Covariance* P);

}  // namespace estimator::localization
