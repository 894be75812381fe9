#pragma once
// The update with a general-purpose (GP) localizer pose: a world pose with
// its 6 x 6 covariance (measurements.hpp has the noise model).
//   r = [p_meas - p;  Log(q_meas q^-1)]           (6-D, world frame)
//   H = [I 0 0 0 0;  0 0 I 0 0]                    (dp, dtheta)
//   R = the pose's covariance
// gated at the 6-D chi-square quantile, Joseph-form update. The filter
// applies it at the pose's capture time (localization_filter.hpp).
#include "estimator/localization/ekf_update.hpp"
#include "estimator/localization/gates.hpp"
#include "estimator/localization/measurements.hpp"
#include "estimator/localization/state.hpp"

namespace estimator::localization {

// kAccepted for a usable pose: finite; |q| within 1e-3 of 1 (it is
// normalised before use); covariance symmetric, positive definite, position
// sigmas under 100 m and attitude sigmas under pi. Otherwise
// kRejectedNotFinite or kRejectedInvalid.
UpdateStatus check_gp_pose(const GpPose& g);

BlockObservation<6> gp_observation(const GpPose& g, const NominalState& x);

// Gate and update at (x, P). On a rejection x and P are untouched.
UpdateResult gp_update(const ChiSquareGate& gate, const GpPose& g, NominalState* x, Covariance* P);

}  // namespace estimator::localization
