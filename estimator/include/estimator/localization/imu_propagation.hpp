#pragma once
// Propagation of the state and its covariance on IMU samples.
//
// Nominal state over [a.t, b.t], dt = b.t - a.t, with the mean of the two
// samples less the biases (w = rate, f = specific force, body frame):
//   q_b = q_a Exp(w dt)                 (body rates: right multiplication)
//   R_m = R(q_a Exp(w dt / 2))          (attitude at mid-step)
//   v_b = v_a + (R_m f + g) dt,  p_b = p_a + v_a dt + (R_m f + g) dt^2 / 2
// Error state (state.hpp), from
//   dp' = dv,  dv' = -[R f x] dtheta - R dba - R n_a,  dtheta' = -R dbg - R n_g,
//   dbg' = n_wg,  dba' = n_wa:
// Phi = I + F dt + F^2 dt^2 / 2 + F^3 dt^3 / 6, exact for R f constant over
// the step, and Q from the noise densities integrated over dt (the velocity
// noise's dt^3 / 3 and dt^2 / 2 terms in position included). Phi is block
// upper triangular with identity diagonal blocks; P = Phi P Phi^T is formed
// from its eight non-trivial 3 x 3 blocks (about a third of the work of two
// dense 15 x 15 products, which counts on the Cortex-A8's VFP).
//
// Gaps (config.hpp has the numbers):
//   dt <= max_imu_step_s: one step (kPropagated);
//   dt <= max_imu_gap_s: n = ceil(dt * imu_rate_hz) sub-steps (at most
//     kMaxGapSubsteps) between the two samples linearly interpolated, each
//     with the unmeasured-motion noise added to the sensor's (kGapBridged):
//     the covariance grows with the gap, and a re-propagation repeats it;
//   longer: nothing integrated (the motion is unknown); position, velocity
//     and attitude held and their variances inflated by the lost_* sigmas
//     (kGapLost). The filter then flags the estimate lost until an absolute
//     update is accepted, which the inflated covariance lets through.
#include <Eigen/Core>

#include "estimator/localization/config.hpp"
#include "estimator/localization/measurements.hpp"
#include "estimator/localization/state.hpp"
#include "estimator/localization/status.hpp"

namespace estimator::localization {

// The sample at t on the line between a and b (a.t <= t <= b.t, a.t < b.t).
ImuSample interpolate(const ImuSample& a, const ImuSample& b, std::int64_t t_us);

// The error-state transition of one step, as a dense matrix (for tests: the
// propagation applies it blockwise).
Covariance error_transition(const Eigen::Matrix3d& R_world_body, const Eigen::Vector3d& f_body_mps2,
                            double dt_s);

// One step from a to b, no gap rule. unmeasured adds the gap noise.
void propagate_step(const LocalizationConfig& cfg, const ImuSample& a, const ImuSample& b,
                    bool unmeasured, NominalState* x, Covariance* P);

// Which rule an interval between two samples falls under (kPropagated,
// kGapBridged or kGapLost).
ImuStatus classify_interval(const LocalizationConfig& cfg, std::int64_t dt_us);

// From `from` to `to` (from.t <= to.t; nothing when equal), part or all of
// an interval that classify_interval() put under kPropagated (one step) or
// kGapBridged (sub-steps of at most 1 / imu_rate_hz with the gap noise). A
// re-propagation splits an interval at a measurement's time with this, so
// the split pieces keep their interval's rule.
void propagate_span(const LocalizationConfig& cfg, const ImuSample& from, const ImuSample& to,
                    bool bridged, NominalState* x, Covariance* P);

// Inflates the covariance as the kGapLost rule does (state held).
void inflate_lost(const LocalizationConfig& cfg, Covariance* P);

// From a to b with the gap rule above. b.t > a.t.
ImuStatus propagate_interval(const LocalizationConfig& cfg, const ImuSample& a, const ImuSample& b,
                             NominalState* x, Covariance* P);

}  // namespace estimator::localization
