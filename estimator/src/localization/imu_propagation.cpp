#include "estimator/localization/imu_propagation.hpp"

#include <algorithm>
#include <cmath>

#include "estimator/localization/covariance_check.hpp"
#include "estimator/localization/so3.hpp"

namespace estimator::localization {
namespace {

// The non-trivial blocks of Phi (the rest: identity on the diagonal, zero).
struct TransitionBlocks {
  double dt;
  Eigen::Matrix3d p_att, p_bg, p_ba, v_att, v_bg, v_ba, att_bg;
};

TransitionBlocks transition_blocks(const Eigen::Matrix3d& R, const Eigen::Vector3d& f, double dt) {
  const Eigen::Matrix3d Sf = skew(R * f);
  const Eigen::Matrix3d SfR = Sf * R;
  const double dt2 = dt * dt, dt3 = dt2 * dt;
  TransitionBlocks b;
  b.dt = dt;
  b.p_att = -0.5 * dt2 * Sf;
  b.p_bg = (dt3 / 6.0) * SfR;
  b.p_ba = -0.5 * dt2 * R;
  b.v_att = -dt * Sf;
  b.v_bg = 0.5 * dt2 * SfR;
  b.v_ba = -dt * R;
  b.att_bg = -dt * R;
  return b;
}

// P = Phi P Phi^T from the blocks: M = Phi P by block rows, then M Phi^T by
// block columns. lazyProduct(): coefficient-based, as in ekf_update.cpp.
void apply_transition(const TransitionBlocks& b, Covariance* P) {
  const Covariance& Q = *P;
  Covariance M;
  M.middleRows<3>(kPos) = Q.middleRows<3>(kPos) + b.dt * Q.middleRows<3>(kVel) +
                          b.p_att.lazyProduct(Q.middleRows<3>(kAtt)) +
                          b.p_bg.lazyProduct(Q.middleRows<3>(kGyroBias)) +
                          b.p_ba.lazyProduct(Q.middleRows<3>(kAccelBias));
  M.middleRows<3>(kVel) = Q.middleRows<3>(kVel) + b.v_att.lazyProduct(Q.middleRows<3>(kAtt)) +
                          b.v_bg.lazyProduct(Q.middleRows<3>(kGyroBias)) +
                          b.v_ba.lazyProduct(Q.middleRows<3>(kAccelBias));
  M.middleRows<3>(kAtt) = Q.middleRows<3>(kAtt) + b.att_bg.lazyProduct(Q.middleRows<3>(kGyroBias));
  M.middleRows<12>(kGyroBias) = Q.middleRows<12>(kGyroBias);  // biases and map: identity

  Covariance& out = *P;
  out.middleCols<3>(kPos) = M.middleCols<3>(kPos) + b.dt * M.middleCols<3>(kVel) +
                            M.middleCols<3>(kAtt).lazyProduct(b.p_att.transpose()) +
                            M.middleCols<3>(kGyroBias).lazyProduct(b.p_bg.transpose()) +
                            M.middleCols<3>(kAccelBias).lazyProduct(b.p_ba.transpose());
  out.middleCols<3>(kVel) = M.middleCols<3>(kVel) +
                            M.middleCols<3>(kAtt).lazyProduct(b.v_att.transpose()) +
                            M.middleCols<3>(kGyroBias).lazyProduct(b.v_bg.transpose()) +
                            M.middleCols<3>(kAccelBias).lazyProduct(b.v_ba.transpose());
  out.middleCols<3>(kAtt) =
      M.middleCols<3>(kAtt) + M.middleCols<3>(kGyroBias).lazyProduct(b.att_bg.transpose());
  out.middleCols<12>(kGyroBias) = M.middleCols<12>(kGyroBias);
}

void add_diagonal(Covariance* P, int block, double variance) {
  for (int i = 0; i < 3; ++i) (*P)(block + i, block + i) += variance;
}

}  // namespace

ImuSample interpolate(const ImuSample& a, const ImuSample& b, std::int64_t t_us) {
  if (t_us <= a.t_us) return a;
  if (t_us >= b.t_us) return b;
  const double s = static_cast<double>(t_us - a.t_us) / static_cast<double>(b.t_us - a.t_us);
  ImuSample out;
  out.t_us = t_us;
  out.omega_body_radps = a.omega_body_radps + s * (b.omega_body_radps - a.omega_body_radps);
  out.a_body_mps2 = a.a_body_mps2 + s * (b.a_body_mps2 - a.a_body_mps2);
  return out;
}

Covariance error_transition(const Eigen::Matrix3d& R_world_body, const Eigen::Vector3d& f_body_mps2,
                            double dt_s) {
  const TransitionBlocks b = transition_blocks(R_world_body, f_body_mps2, dt_s);
  Covariance Phi = Covariance::Identity();
  Phi.block<3, 3>(kPos, kVel) = dt_s * Eigen::Matrix3d::Identity();
  Phi.block<3, 3>(kPos, kAtt) = b.p_att;
  Phi.block<3, 3>(kPos, kGyroBias) = b.p_bg;
  Phi.block<3, 3>(kPos, kAccelBias) = b.p_ba;
  Phi.block<3, 3>(kVel, kAtt) = b.v_att;
  Phi.block<3, 3>(kVel, kGyroBias) = b.v_bg;
  Phi.block<3, 3>(kVel, kAccelBias) = b.v_ba;
  Phi.block<3, 3>(kAtt, kGyroBias) = b.att_bg;
  return Phi;
}

void propagate_step(const LocalizationConfig& cfg, const ImuSample& a, const ImuSample& b,
                    bool unmeasured, NominalState* x, Covariance* P) {
  const double dt = 1e-6 * static_cast<double>(b.t_us - a.t_us);
  const Eigen::Vector3d w = 0.5 * (a.omega_body_radps + b.omega_body_radps) - x->gyro_bias_radps;
  const Eigen::Vector3d f = 0.5 * (a.a_body_mps2 + b.a_body_mps2) - x->accel_bias_mps2;
  const Eigen::Quaterniond q0 = x->q_world_body;
  const Eigen::Matrix3d R_mid = (q0 * quat_exp(0.5 * dt * w)).toRotationMatrix();
  const Eigen::Vector3d a_world = R_mid * f + cfg.g_world_mps2;

  x->p_world_body_m += dt * x->v_world_body_mps + 0.5 * dt * dt * a_world;
  x->v_world_body_mps += dt * a_world;
  x->q_world_body = (q0 * quat_exp(dt * w)).normalized();

  apply_transition(transition_blocks(R_mid, f, dt), P);

  const ImuNoise& n = cfg.imu;
  double accel_var = n.accel_noise_mps2_rthz * n.accel_noise_mps2_rthz;
  double rate_var = n.gyro_noise_radps_rthz * n.gyro_noise_radps_rthz;
  if (unmeasured) {
    accel_var += cfg.gap_accel_sigma_mps2_rthz * cfg.gap_accel_sigma_mps2_rthz;
    rate_var += cfg.gap_rate_sigma_radps_rthz * cfg.gap_rate_sigma_radps_rthz;
  }
  // White acceleration integrated twice: [dt^3/3, dt^2/2; dt^2/2, dt].
  add_diagonal(P, kPos, accel_var * dt * dt * dt / 3.0);
  for (int i = 0; i < 3; ++i) {
    (*P)(kPos + i, kVel + i) += accel_var * dt * dt / 2.0;
    (*P)(kVel + i, kPos + i) += accel_var * dt * dt / 2.0;
  }
  add_diagonal(P, kVel, accel_var * dt);
  add_diagonal(P, kAtt, rate_var * dt);
  add_diagonal(P, kGyroBias, n.gyro_bias_rw_radps2_rthz * n.gyro_bias_rw_radps2_rthz * dt);
  add_diagonal(P, kAccelBias, n.accel_bias_rw_mps3_rthz * n.accel_bias_rw_mps3_rthz * dt);
  symmetrize(P);
}

ImuStatus classify_interval(const LocalizationConfig& cfg, std::int64_t dt_us) {
  const double dt = 1e-6 * static_cast<double>(dt_us);
  if (dt <= cfg.max_imu_step_s) return ImuStatus::kPropagated;
  if (dt <= cfg.max_imu_gap_s) return ImuStatus::kGapBridged;
  return ImuStatus::kGapLost;
}

void propagate_span(const LocalizationConfig& cfg, const ImuSample& from, const ImuSample& to,
                    bool bridged, NominalState* x, Covariance* P) {
  const std::int64_t span = to.t_us - from.t_us;
  if (span <= 0) return;
  if (!bridged) {
    propagate_step(cfg, from, to, false, x, P);
    return;
  }
  const double dt = 1e-6 * static_cast<double>(span);
  const int n =
      std::clamp(static_cast<int>(std::ceil(dt * cfg.imu_rate_hz - 1e-9)), 1, kMaxGapSubsteps);
  ImuSample s0 = from;
  for (int i = 1; i <= n; ++i) {
    const ImuSample s1 = i == n ? to : interpolate(from, to, from.t_us + span * i / n);
    propagate_step(cfg, s0, s1, true, x, P);
    s0 = s1;
  }
}

void inflate_lost(const LocalizationConfig& cfg, Covariance* P) {
  add_diagonal(P, kPos, cfg.lost_position_sigma_m * cfg.lost_position_sigma_m);
  add_diagonal(P, kVel, cfg.lost_velocity_sigma_mps * cfg.lost_velocity_sigma_mps);
  add_diagonal(P, kAtt, cfg.lost_attitude_sigma_rad * cfg.lost_attitude_sigma_rad);
}

ImuStatus propagate_interval(const LocalizationConfig& cfg, const ImuSample& a, const ImuSample& b,
                             NominalState* x, Covariance* P) {
  const ImuStatus rule = classify_interval(cfg, b.t_us - a.t_us);
  if (rule == ImuStatus::kGapLost) {
    inflate_lost(cfg, P);
  } else {
    propagate_span(cfg, a, b, rule == ImuStatus::kGapBridged, x, P);
  }
  return rule;
}

}  // namespace estimator::localization
