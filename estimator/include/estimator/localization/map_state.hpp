#pragma once
// Putting a handrail map into the filter's state (state.hpp: the map's
// error is the last six of the error state) with the uncertainty it really
// has, and keeping the block harmless while there is no map.
//
// A map from sightings, T_world_handrail = T_world_body T_body_cam
// T_cam_handrail, inherits the robot's pose error at the time:
//   dp_map  = dp - [(p_map - p_body) x] dtheta + e_p
//   dth_map = dtheta + e_theta
// (e: the detections' own error, independent of the robot's). So its
// covariance is J P J^T + E and its cross-covariance with the rest J P,
// with J the 6 x 21 map of the robot's pose error above. Relative to the
// robot at that moment the map is then as good as the detection; in the
// world, no better than the robot was.
//
// A survey is known independently of the robot: its block is the survey's
// sigmas, uncorrelated.
#include "estimator/localization/config.hpp"
#include "estimator/localization/handrail_map.hpp"
#include "estimator/localization/state.hpp"

namespace estimator::localization {

// The map block's placeholder while there is no map: 1 m and 1 rad,
// uncorrelated. Nothing observes it.
void clear_map_block(Covariance* P);

// The map T_world_handrail, placed from the robot's pose in *x, into *x and
// *P as above (E from cfg.map_sighting_*).
void attach_sighted_map(const LocalizationConfig& cfg, const Eigen::Isometry3d& T_world_handrail,
                        NominalState* x, Covariance* P);

// A checked survey into *x and *P, uncorrelated with the robot.
void attach_surveyed_map(const HandrailMap& survey, NominalState* x, Covariance* P);

// The body's position in the handrail's frame, p_H = R_WH^T (p - p_map),
// what perching needs, and its covariance: with r = p - p_map,
// dp_H = R_WH^T (dp - dp_map + [r x] dth_map). The world covariance holds
// the map's uncertainty; this one is what the handrail updates know.
Eigen::Vector3d body_in_handrail(const NominalState& x);
Eigen::Matrix3d body_in_handrail_cov(const NominalState& x, const Covariance& P);

}  // namespace estimator::localization
