#include "estimator/localization/localization_filter.hpp"

#include <algorithm>
#include <cmath>

#include "estimator/localization/covariance_check.hpp"
#include "estimator/localization/handrail_update.hpp"
#include "estimator/localization/imu_propagation.hpp"
#include "estimator/localization/map_state.hpp"
#include "estimator/localization/pose_update.hpp"
#include "estimator/localization/so3.hpp"

namespace estimator::localization {
namespace {

MeasurementKind handrail_kind(HandrailState s) {
  return s == HandrailState::kNoEnd ? MeasurementKind::kHandrailNoEnd
                                    : MeasurementKind::kHandrailEnds;
}

std::int64_t seconds_to_us(double s) {
  return static_cast<std::int64_t>(std::llround(s * 1e6));
}

// The covariance to start from: the pose's for position and attitude, the
// configured sigmas for the rest.
Covariance initial_covariance(const LocalizationConfig& cfg, const PoseCovariance& pose) {
  Covariance P = Covariance::Zero();
  P.block<3, 3>(kPos, kPos) = pose.block<3, 3>(0, 0);
  P.block<3, 3>(kPos, kAtt) = pose.block<3, 3>(0, 3);
  P.block<3, 3>(kAtt, kPos) = pose.block<3, 3>(3, 0);
  P.block<3, 3>(kAtt, kAtt) = pose.block<3, 3>(3, 3);
  const auto set = [&](int block, double sigma) {
    P.block<3, 3>(block, block) = sigma * sigma * Eigen::Matrix3d::Identity();
  };
  set(kVel, cfg.init_velocity_sigma_mps);
  set(kGyroBias, cfg.init_gyro_bias_sigma_radps);
  set(kAccelBias, cfg.init_accel_bias_sigma_mps2);
  clear_map_block(&P);
  return P;
}

}  // namespace

LocalizationFilter::LocalizationFilter(const LocalizationConfig& cfg)
    : cfg_(cfg), config_error_(validate(cfg)), gate_(config_error_ ? 0.999 : cfg.gate_probability) {
  if (!config_error_) default_P_ = initial_covariance(cfg_, PoseCovariance::Identity());
}

void LocalizationFilter::reset() {
  history_.clear();
  store_.clear();
  map_.reset();
  ends_map_.reset();
  if (survey_.valid) map_.set_survey(survey_);
  ++map_generation_;
  last_ = UpdateResult{};
  initialized_ = lost_ = false;
  floor_us_ = 0;
  have_handrail_accept_ = false;
  handrail_rejections_in_row_ = gp_rejections_in_row_ = gp_any_rejections_in_row_ = 0;
}

void LocalizationFilter::reset_handrail_map() {
  drop_map();
  put_back_survey();
}

UpdateStatus LocalizationFilter::set_handrail_survey(const HandrailMap& survey) {
  const UpdateStatus st = check_survey(survey);
  if (st != UpdateStatus::kAccepted) return st;
  survey_ = survey;
  survey_.valid = survey_.surveyed = true;
  drop_map();
  put_back_survey();
  return st;
}

void LocalizationFilter::clear_handrail_survey() {
  survey_ = HandrailMap{};
  drop_map();
}

void LocalizationFilter::drop_map() {
  map_.reset();
  ends_map_.reset();
  if (survey_.valid) map_.set_survey(survey_);
  // Stored handrail updates made against the old map are skipped on a
  // re-propagation from now on.
  ++map_generation_;
  have_handrail_accept_ = false;
  handrail_rejections_in_row_ = 0;
}

void LocalizationFilter::put_back_survey() {
  if (!survey_.valid || !initialized_ || history_.empty() || !history_.newest().has_state) return;
  Prior& pr = prior_;
  if (!prior_at(time_us(), &pr)) return;
  attach_map_at(pr, survey_);
}

void LocalizationFilter::attach_map_at(const Prior& pr, const HandrailMap& map) {
  StoredMeasurement& ev = scratch_;
  ev.kind = MeasurementKind::kHandrailEnds;
  ev.t_us = pr.t_us;
  ev.seq = ++seq_;
  ev.map_generation = map_generation_;
  ev.map_attach = true;
  ev.map = map;
  NominalState x = pr.x;
  Covariance P = pr.P;
  if (map.surveyed) {
    attach_surveyed_map(map, &x, &P);
  } else {
    attach_sighted_map(cfg_, map.T_world_handrail, &x, &P);
  }
  store_and_replay(ev, pr, x, P);
}

HandrailMap LocalizationFilter::handrail_map() const {
  HandrailMap m = map_.map();
  if (m.valid && initialized_) {
    const NominalState& x = state();
    m.T_world_handrail.linear() = x.q_world_handrail.toRotationMatrix();
    m.T_world_handrail.translation() = x.p_world_handrail_m;
  }
  return m;
}

bool LocalizationFilter::handrail_holding() const {
  if (!map_.map().valid || !have_handrail_accept_ || history_.empty()) return false;
  return time_us() - last_handrail_accept_us_ <= seconds_to_us(cfg_.handrail_hold_s);
}

std::int64_t LocalizationFilter::time_us() const {
  return history_.empty() ? 0 : history_.newest().imu.t_us;
}

const NominalState& LocalizationFilter::state() const {
  return initialized_ && !history_.empty() && history_.newest().has_state ? history_.newest().x
                                                                          : default_state_;
}

const Covariance& LocalizationFilter::covariance() const {
  return initialized_ && !history_.empty() && history_.newest().has_state ? history_.newest().P
                                                                          : default_P_;
}

Health LocalizationFilter::check() const {
  return check_filter(state(), covariance());
}

PoseEstimate LocalizationFilter::estimate() const {
  PoseEstimate e;
  const NominalState& x = state();
  const Covariance& P = covariance();
  e.initialized = initialized_;
  e.lost = lost_;
  e.handrail_map_valid = map_.map().valid;
  e.handrail_holding = handrail_holding();
  e.t_us = time_us();
  e.p_world_body_m = x.p_world_body_m;
  e.v_world_body_mps = x.v_world_body_mps;
  e.q_world_body = x.q_world_body;
  e.gyro_bias_radps = x.gyro_bias_radps;
  e.accel_bias_mps2 = x.accel_bias_mps2;
  e.pose_cov.block<3, 3>(0, 0) = P.block<3, 3>(kPos, kPos);
  e.pose_cov.block<3, 3>(0, 3) = P.block<3, 3>(kPos, kAtt);
  e.pose_cov.block<3, 3>(3, 0) = P.block<3, 3>(kAtt, kPos);
  e.pose_cov.block<3, 3>(3, 3) = P.block<3, 3>(kAtt, kAtt);
  e.velocity_cov = P.block<3, 3>(kVel, kVel);
  if (e.handrail_map_valid && initialized_) {
    e.p_handrail_body_m = body_in_handrail(x);
    e.handrail_position_cov = body_in_handrail_cov(x, P);
  }
  return e;
}

// ---------------------------------------------------------------- IMU

ImuStatus LocalizationFilter::add_imu(const ImuSample& s) {
  ImuStatus st;
  if (config_error_) {
    st = ImuStatus::kRejectedBadConfig;
  } else if (!s.omega_body_radps.allFinite() || !s.a_body_mps2.allFinite()) {
    st = ImuStatus::kRejectedNotFinite;
  } else if (s.omega_body_radps.norm() > cfg_.max_rate_radps ||
             s.a_body_mps2.norm() > cfg_.max_accel_mps2) {
    st = ImuStatus::kRejectedOutOfRange;
  } else if (!history_.empty() && s.t_us <= history_.newest().imu.t_us) {
    st = ImuStatus::kRejectedOutOfOrder;
  } else if (!initialized_) {
    history_.push(s);
    st = ImuStatus::kBuffered;
  } else {
    const HistoryEntry& prev = history_.newest();
    NominalState x = prev.x;
    Covariance P = prev.P;
    const ImuSample a = prev.imu;
    st = propagate_interval(cfg_, a, s, &x, &P);
    HistoryEntry& e = history_.push(s);
    e.x = x;
    e.P = P;
    e.has_state = true;
    if (st == ImuStatus::kGapLost) {
      // Nothing before the gap can be re-propagated across it.
      lost_ = true;
      floor_us_ = s.t_us;
      store_.clear();
    }
    // Stored updates at or before the oldest entry are in it for good.
    store_.drop_before(history_.at(0).imu.t_us + 1);
  }
  counters_.note(st);
  return st;
}

// ------------------------------------------------------- history and replay

UpdateStatus LocalizationFilter::time_check(std::int64_t t_us, std::int64_t* t_eff) const {
  const std::int64_t newest = history_.newest().imu.t_us;
  if (t_us > newest + seconds_to_us(cfg_.max_future_s)) return UpdateStatus::kRejectedInFuture;
  *t_eff = std::min(t_us, newest);
  if (*t_eff < floor_us_ || *t_eff < history_.at(0).imu.t_us) return UpdateStatus::kRejectedTooOld;
  return UpdateStatus::kAccepted;
}

void LocalizationFilter::raise_floor_past(std::int64_t t_us) {
  const int i = history_.find_after(t_us);
  const std::int64_t t = i < history_.size() ? history_.at(i).imu.t_us : time_us();
  floor_us_ = std::max(floor_us_, t);
}

void LocalizationFilter::apply_stored(const StoredMeasurement& m, NominalState* x, Covariance* P) {
  UpdateResult r;
  if (m.map_attach) {
    if (m.map_generation != map_generation_) return;
    if (m.map.surveyed) {
      attach_surveyed_map(m.map, x, P);
    } else {
      attach_sighted_map(cfg_, m.map.T_world_handrail, x, P);
    }
    return;
  }
  if (m.kind == MeasurementKind::kGpPose) {
    r = gp_update(gate_, m.gp, x, P);
  } else {
    if (!map_.map().valid || m.map_generation != map_generation_) return;
    r = handrail_update(cfg_, gate_, m.handrail, x, P);
  }
  if (r.status != UpdateStatus::kAccepted) ++counters_.replay_rejections;
}

bool LocalizationFilter::prior_at(std::int64_t t_us, Prior* pr) {
  const int k = history_.find_at_or_before(t_us);
  if (k < 0 || !history_.at(k).has_state) return false;
  const HistoryEntry& e0 = history_.at(k);
  pr->k = k;
  pr->t_us = t_us;
  pr->x = e0.x;
  pr->P = e0.P;
  int cursor = store_.first_after(e0.imu.t_us);
  if (t_us == e0.imu.t_us) {
    pr->s = e0.imu;
  } else {
    // t lies inside the interval from entry k to k + 1, which keeps its
    // rule (one step or a bridged gap) when split.
    const HistoryEntry& e1 = history_.at(k + 1);
    const bool bridged =
        classify_interval(cfg_, e1.imu.t_us - e0.imu.t_us) == ImuStatus::kGapBridged;
    ImuSample s_prev = e0.imu;
    while (cursor < store_.size() && store_.at(cursor).t_us <= t_us) {
      const ImuSample s_m = interpolate(e0.imu, e1.imu, store_.at(cursor).t_us);
      propagate_span(cfg_, s_prev, s_m, bridged, &pr->x, &pr->P);
      apply_stored(store_.at(cursor), &pr->x, &pr->P);
      s_prev = s_m;
      ++cursor;
    }
    pr->s = interpolate(e0.imu, e1.imu, t_us);
    propagate_span(cfg_, s_prev, pr->s, bridged, &pr->x, &pr->P);
  }
  pr->next_store = cursor;
  return true;
}

void LocalizationFilter::replay(int k, NominalState x, Covariance P, ImuSample s_prev, int cursor) {
  for (int i = k + 1; i < history_.size(); ++i) {
    const ImuSample a = history_.at(i - 1).imu;
    HistoryEntry& e = history_.at(i);
    const ImuStatus rule = classify_interval(cfg_, e.imu.t_us - a.t_us);
    if (rule == ImuStatus::kGapLost) {
      // Not reached (a lost gap moves the floor past itself), kept for the
      // rule's sake: the same inflation as when the sample came.
      inflate_lost(cfg_, &P);
    } else {
      const bool bridged = rule == ImuStatus::kGapBridged;
      while (cursor < store_.size() && store_.at(cursor).t_us <= e.imu.t_us) {
        const ImuSample s_m = interpolate(a, e.imu, store_.at(cursor).t_us);
        propagate_span(cfg_, s_prev, s_m, bridged, &x, &P);
        apply_stored(store_.at(cursor), &x, &P);
        s_prev = s_m;
        ++cursor;
      }
      propagate_span(cfg_, s_prev, e.imu, bridged, &x, &P);
    }
    e.x = x;
    e.P = P;
    e.has_state = true;
    s_prev = e.imu;
  }
}

void LocalizationFilter::store_and_replay(const StoredMeasurement& m, const Prior& pr,
                                          const NominalState& x, const Covariance& P) {
  bool evicted = false;
  std::int64_t evicted_t = 0;
  const int idx = store_.insert(m, &evicted, &evicted_t);
  if (evicted) {
    // A re-propagation from before the dropped update would lose it.
    ++counters_.store_evictions;
    raise_floor_past(evicted_t);
  }
  if (pr.t_us == history_.at(pr.k).imu.t_us) {
    // At a sample's own time: that entry takes the updated state.
    HistoryEntry& e = history_.at(pr.k);
    e.x = x;
    e.P = P;
  }
  replay(pr.k, x, P, pr.s, idx + 1);
}

void LocalizationFilter::restart_at(const Prior& pr, const NominalState& x, const Covariance& P) {
  HistoryEntry& e = history_.at(pr.k);
  if (pr.t_us == e.imu.t_us) {
    e.x = x;
    e.P = P;
    e.has_state = true;
    floor_us_ = e.imu.t_us;
  } else {
    floor_us_ = history_.at(pr.k + 1).imu.t_us;
  }
  replay(pr.k, x, P, pr.s, store_.size());
}

// ---------------------------------------------------------------- GP pose

UpdateStatus LocalizationFilter::initialize_from(const GpPose& g, std::int64_t t_eff) {
  const int k = history_.find_at_or_before(t_eff);
  Prior& pr = prior_;
  pr.k = k;
  pr.t_us = t_eff;
  const HistoryEntry& e0 = history_.at(k);
  pr.s = t_eff == e0.imu.t_us ? e0.imu : interpolate(e0.imu, history_.at(k + 1).imu, t_eff);
  NominalState x;
  x.p_world_body_m = g.p_world_body_m;
  x.q_world_body = g.q_world_body.normalized();
  x.gyro_bias_radps = cfg_.init_gyro_bias_radps;
  x.accel_bias_mps2 = cfg_.init_accel_bias_mps2;
  store_.clear();
  initialized_ = true;
  lost_ = false;
  Covariance P = initial_covariance(cfg_, g.cov);
  // A survey is the map from the start.
  if (survey_.valid) attach_surveyed_map(survey_, &x, &P);
  restart_at(pr, x, P);
  return UpdateStatus::kInitialized;
}

UpdateStatus LocalizationFilter::relocalize_to(const GpPose& g, const Prior& pr,
                                               bool reset_dynamics) {
  NominalState x = pr.x;
  x.p_world_body_m = g.p_world_body_m;
  x.q_world_body = g.q_world_body.normalized();
  const Covariance pose = initial_covariance(cfg_, g.cov);
  Covariance P = pr.P;
  if (reset_dynamics) {
    x.v_world_body_mps.setZero();
    x.gyro_bias_radps = cfg_.init_gyro_bias_radps;
    x.accel_bias_mps2 = cfg_.init_accel_bias_mps2;
    P = pose;
    ++counters_.reinitializations;
  } else {
    // Position and attitude start again from the pose; their correlations
    // with the rest are gone with the old estimate.
    for (int block : {kPos, kAtt}) {
      P.middleRows<3>(block).setZero();
      P.middleCols<3>(block).setZero();
    }
    P.block<3, 3>(kPos, kPos) = pose.block<3, 3>(kPos, kPos);
    P.block<3, 3>(kPos, kAtt) = pose.block<3, 3>(kPos, kAtt);
    P.block<3, 3>(kAtt, kPos) = pose.block<3, 3>(kAtt, kPos);
    P.block<3, 3>(kAtt, kAtt) = pose.block<3, 3>(kAtt, kAtt);
  }
  store_.clear();
  if (map_.map().valid) ++counters_.map_resets;
  drop_map();
  // The map went with the old estimate; a survey is independent of it.
  if (survey_.valid) {
    attach_surveyed_map(survey_, &x, &P);
  } else {
    clear_map_block(&P);
  }
  lost_ = false;
  gp_rejections_in_row_ = gp_any_rejections_in_row_ = 0;
  restart_at(pr, x, P);
  return UpdateStatus::kRelocalized;
}

UpdateStatus LocalizationFilter::add_gp_pose(const GpPose& g) {
  const MeasurementKind kind = MeasurementKind::kGpPose;
  UpdateStatus st = config_error_ ? UpdateStatus::kRejectedBadConfig : check_gp_pose(g);
  std::int64_t t_eff = 0;
  last_ = UpdateResult{};
  if (st == UpdateStatus::kAccepted && history_.empty()) st = UpdateStatus::kRejectedNotInitialized;
  if (st == UpdateStatus::kAccepted && !initialized_) {
    const std::int64_t newest = history_.newest().imu.t_us;
    if (g.capture_time_us > newest + seconds_to_us(cfg_.max_future_s)) {
      st = UpdateStatus::kRejectedInFuture;
    } else {
      st = initialize_from(g, std::clamp(g.capture_time_us, history_.at(0).imu.t_us, newest));
    }
    last_.status = st;
    counters_.note(kind, st);
    return st;
  }
  if (st == UpdateStatus::kAccepted) st = time_check(g.capture_time_us, &t_eff);
  Prior& pr = prior_;
  if (st == UpdateStatus::kAccepted && !prior_at(t_eff, &pr)) st = UpdateStatus::kRejectedTooOld;
  if (st != UpdateStatus::kAccepted) {
    last_.status = st;
    counters_.note(kind, st);
    return st;
  }

  // The pose's jump from the filter, for the relocalisation rule.
  const Eigen::Vector3d dp = g.p_world_body_m - pr.x.p_world_body_m;
  const Eigen::Vector3d dtheta =
      quat_log(g.q_world_body.normalized() * pr.x.q_world_body.conjugate());
  const bool near_filter =
      dp.norm() <= cfg_.relocalize_agreement_m && dtheta.norm() <= cfg_.relocalize_agreement_rad;
  const bool continues_jump =
      gp_rejections_in_row_ > 0 && !near_filter &&
      (dp - last_rejected_dp_).norm() <= cfg_.relocalize_agreement_m &&
      (dtheta - last_rejected_dtheta_).norm() <= cfg_.relocalize_agreement_rad;
  NominalState x = pr.x;
  Covariance P = pr.P;
  if (continues_jump && !handrail_holding()) {
    // Judged with the jump it agrees with, not by the gate: the covariance
    // grown since the first rejection must not let a jumped pose pull the
    // state part way.
    last_.status = UpdateStatus::kRejectedJump;
    last_.dof = 6;
  } else {
    last_ = gp_update(gate_, g, &x, &P);
  }
  st = last_.status;
  if (st == UpdateStatus::kAccepted) {
    gp_rejections_in_row_ = gp_any_rejections_in_row_ = 0;
    lost_ = false;
    StoredMeasurement& m = scratch_;
    m.kind = kind;
    m.t_us = t_eff;
    m.seq = ++seq_;
    m.map_attach = false;
    m.gp = g;
    store_and_replay(m, pr, x, P);
  } else if (st == UpdateStatus::kRejectedGate || st == UpdateStatus::kRejectedJump) {
    if (handrail_holding()) {
      gp_rejections_in_row_ = gp_any_rejections_in_row_ = 0;
    } else {
      gp_rejections_in_row_ = st == UpdateStatus::kRejectedJump ? gp_rejections_in_row_ + 1 : 1;
      ++gp_any_rejections_in_row_;
      last_rejected_dp_ = dp;
      last_rejected_dtheta_ = dtheta;
      // The rejections before were counted as such; this one is the move.
      if (gp_rejections_in_row_ >= cfg_.relocalize_after) {
        st = relocalize_to(g, pr, /*reset_dynamics=*/false);
        last_.status = st;
      } else if (gp_any_rejections_in_row_ >= cfg_.reinitialize_after) {
        st = relocalize_to(g, pr, /*reset_dynamics=*/true);
        last_.status = st;
      }
    }
  }
  counters_.note(kind, st);
  return st;
}

// ---------------------------------------------------------------- handrail

UpdateStatus LocalizationFilter::add_handrail(const HandrailMeasurement& m) {
  const MeasurementKind kind = handrail_kind(m.state);
  UpdateStatus st =
      config_error_ ? UpdateStatus::kRejectedBadConfig : check_handrail_measurement(m);
  std::int64_t t_eff = 0;
  last_ = UpdateResult{};
  if (st == UpdateStatus::kAccepted && (!initialized_ || history_.empty())) {
    st = UpdateStatus::kRejectedNotInitialized;
  }
  if (st == UpdateStatus::kAccepted) st = time_check(m.capture_time_us, &t_eff);
  Prior& pr = prior_;
  if (st == UpdateStatus::kAccepted && !prior_at(t_eff, &pr)) st = UpdateStatus::kRejectedTooOld;
  if (st != UpdateStatus::kAccepted) {
    last_.status = st;
    counters_.note(kind, st);
    return st;
  }

  const bool end_seen = m.state != HandrailState::kNoEnd;
  // T_world_handrail of this sighting, from the pose at its capture.
  const auto sighting_in_world = [&]() {
    Eigen::Isometry3d T_world_body = Eigen::Isometry3d::Identity();
    T_world_body.linear() = pr.x.q_world_body.toRotationMatrix();
    T_world_body.translation() = pr.x.p_world_body_m;
    return Eigen::Isometry3d(T_world_body * cfg_.T_body_cam * m.T_cam_handrail);
  };
  // With a line map (built with no end seen), sightings with an end count
  // toward a map placed along the bar, which replaces it when complete;
  // meanwhile each is used as NE against the line map.
  bool as_no_end = false;
  const double position_sigma_m = std::sqrt(pr.P.block<3, 3>(kPos, kPos).diagonal().maxCoeff());
  const bool pose_good_enough = position_sigma_m <= cfg_.map_init_max_position_sigma_m;
  if (map_.map().valid && !map_.map().along_known && end_seen) as_no_end = true;
  if (as_no_end && pose_good_enough) {
    bool restarted = false;
    const UpdateStatus pending =
        ends_map_.add_sighting(cfg_, sighting_in_world(), true, &restarted);
    if (restarted) ++counters_.map_restarts;
    if (pending == UpdateStatus::kMapInitialized) {
      map_ = ends_map_;
      ends_map_.reset();
      ++map_generation_;
      ++counters_.map_line_replaced;
      have_handrail_accept_ = false;
      handrail_rejections_in_row_ = 0;
      attach_map_at(pr, map_.map());
      last_.status = pending;
      counters_.note(kind, pending);
      return pending;
    }
  }
  if (!map_.map().valid) {
    if (!pose_good_enough) {
      st = UpdateStatus::kNoMap;
    } else {
      bool restarted = false;
      st = map_.add_sighting(cfg_, sighting_in_world(), end_seen, &restarted);
      if (restarted) ++counters_.map_restarts;
      if (st == UpdateStatus::kMapInitialized) {
        ++map_generation_;
        handrail_rejections_in_row_ = 0;
        attach_map_at(pr, map_.map());
      }
    }
    last_.status = st;
    counters_.note(kind, st);
    return st;
  }

  StoredMeasurement& sm = scratch_;
  select_features(m, cfg_.max_bar_features, cfg_.max_wall_features, &sm.handrail);
  if (as_no_end) sm.handrail.state = HandrailState::kNoEnd;
  align_with_map(pr.x, cfg_.T_body_cam, &sm.handrail);
  NominalState x = pr.x;
  Covariance P = pr.P;
  last_ = handrail_update(cfg_, gate_, sm.handrail, &x, &P);
  st = last_.status;
  counters_.features_gated += static_cast<std::uint32_t>(last_.features_gated);
  if (st == UpdateStatus::kAccepted) {
    handrail_rejections_in_row_ = 0;
    lost_ = false;
    last_handrail_accept_us_ =
        have_handrail_accept_ ? std::max(last_handrail_accept_us_, t_eff) : t_eff;
    have_handrail_accept_ = true;
    sm.kind = kind;
    sm.t_us = t_eff;
    sm.seq = ++seq_;
    sm.map_generation = map_generation_;
    sm.map_attach = false;
    store_and_replay(sm, pr, x, P);
  } else if (st == UpdateStatus::kRejectedGate) {
    if (++handrail_rejections_in_row_ >= cfg_.map_reset_after_rejections) {
      drop_map();
      put_back_survey();
      ++counters_.map_resets;
    }
  }
  counters_.note(kind, st);
  return st;
}

}  // namespace estimator::localization
