// Faults with defined outcomes, one test each, on the simulated world
// (test_localization_sim.hpp):
//   IMU samples missing for 0.5 s  -> bridged (GAP_BRIDGED): propagated in
//                                     sub-steps with extra noise, covariance
//                                     grows, the estimate stays on track;
//   missing for 2 s                -> GAP_LOST: held, covariance inflated,
//                                     flagged lost until an absolute fix;
//   a handrail measurement 5 cm off -> REJECTED_GATE, counted, state untouched;
//   1 cm off for 3 frames          -> taken, the error bounded (under 15 mm)
//                                     and gone 2 s later;
//   ten of them in a row           -> the map is dropped and built again;
//   no end seen before a map       -> a line map, for NE updates; replaced
//                                     by a map with ends once they are seen;
//   NaN, infinity or malformed input of any kind -> rejected, counted, the
//                                     state untouched (bit for bit);
//   too old, from the future, bad configuration -> their statuses.
// The general-purpose localizer's faults (a jump, a glitch, a divergence)
// are in test_localization_gp_faults.cpp.
// The state and covariance are checked after every step of every run.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <vector>

#include "cmocka_cpp.hpp"
#include "estimator/localization/localization_filter.hpp"
#include "localization_fault_helpers.hpp"
#include "test_localization_sim.hpp"

using namespace estimator::localization;
using estimator::HandrailState;
using faulttest::Converged;
using faulttest::rel_error;
using faulttest::same;
using faulttest::snap;
using faulttest::Snapshot;
using locsim::Event;
using locsim::Sim;
using locsim::SimConfig;

namespace {

const double kNaN = std::numeric_limits<double>::quiet_NaN();
const double kInf = std::numeric_limits<double>::infinity();

// ------------------------------------------------------------- IMU gaps

void test_imu_gap_half_second_is_bridged(void**) {
  SimConfig sc;
  sc.seed = 31;
  sc.duration_s = 30.0;
  Sim sim(sc);
  auto f = std::make_unique<LocalizationFilter>(locsim::sim_filter_config(sc));
  const int gap_from = locsim::sample_at(sim, 15.0), gap_to = locsim::sample_at(sim, 15.5);
  double sigma_before = 0.0, sigma_after = 0.0, err_after = 0.0, err_end = 0.0;
  int bad_health = 0, in_future = 0;
  ImuStatus after_gap = ImuStatus::kPropagated;
  locsim::run_events(
      sim, sim.events(), *f,
      [&](int k, double t) {
        if (!f->initialized()) return;
        bad_health += f->check() != Health::kOk;
        // Relative to the bar: the world sigma holds the map's own too.
        const double sigma = std::sqrt(f->estimate().handrail_position_cov.trace());
        if (k == gap_from - 1) sigma_before = sigma;
        if (k == gap_to) {
          sigma_after = sigma;
          err_after = rel_error(*f, sim, t);
        }
        err_end = rel_error(*f, sim, t);
      },
      [&](const Event&, UpdateStatus st) { in_future += st == UpdateStatus::kRejectedInFuture; },
      [&](int k) {
        if (k == gap_to) {
          // Peek at the status of the first sample after the gap.
          after_gap = f->add_imu(sim.imu()[static_cast<std::size_t>(k)]);
          return true;
        }
        return k >= gap_from && k < gap_to;
      });
  std::printf(
      "  0.5 s gap: %s; position sigma %.2f -> %.2f mm; error after it %.2f mm, at the end %.2f "
      "mm; %d measurements captured in the gap rejected as in the future\n",
      to_string(after_gap), 1e3 * sigma_before, 1e3 * sigma_after, 1e3 * err_after, 1e3 * err_end,
      in_future);
  assert_int_equal(static_cast<int>(after_gap), static_cast<int>(ImuStatus::kGapBridged));
  assert_int_equal(f->counters().count(ImuStatus::kGapBridged), 1);
  assert_int_equal(bad_health, 0);
  assert_false(f->lost());
  assert_true(sigma_after > 1.5 * sigma_before);  // the unmeasured motion shows
  assert_true(err_after < 3.0 * sigma_after);
  assert_true(err_after < 0.02);
  assert_true(err_end < 0.006);  // handrail updates pull it back
}

void test_imu_gap_of_two_seconds_is_lost_then_recovers(void**) {
  SimConfig sc;
  sc.seed = 32;
  sc.duration_s = 35.0;
  Sim sim(sc);
  auto f = std::make_unique<LocalizationFilter>(locsim::sim_filter_config(sc));
  const int gap_from = locsim::sample_at(sim, 15.0), gap_to = locsim::sample_at(sim, 17.0);
  ImuStatus after_gap = ImuStatus::kPropagated;
  bool lost_after_gap = false;
  double sigma_after = 0.0, err_end = 0.0;
  int bad_health = 0, too_old = 0;
  locsim::run_events(
      sim, sim.events(), *f,
      [&](int k, double t) {
        if (!f->initialized()) return;
        bad_health += f->check() != Health::kOk;
        if (k == gap_to) {
          lost_after_gap = f->lost();
          sigma_after = std::sqrt(f->covariance()(kPos, kPos));
        }
        err_end = rel_error(*f, sim, t);
      },
      [&](const Event&, UpdateStatus st) { too_old += st == UpdateStatus::kRejectedTooOld; },
      [&](int k) {
        if (k == gap_to) {
          after_gap = f->add_imu(sim.imu()[static_cast<std::size_t>(k)]);
          return true;
        }
        return k >= gap_from && k < gap_to;
      });
  std::printf(
      "  2 s gap: %s, lost %d, position sigma after %.0f mm; %d late measurements too "
      "old; error at the end %.2f mm\n",
      to_string(after_gap), lost_after_gap, 1e3 * sigma_after, too_old, 1e3 * err_end);
  assert_int_equal(static_cast<int>(after_gap), static_cast<int>(ImuStatus::kGapLost));
  assert_true(lost_after_gap);
  assert_true(sigma_after >= 0.5);
  assert_false(f->lost());  // a later update was accepted
  assert_int_equal(bad_health, 0);
  assert_true(err_end < 0.006);
}

// ------------------------------------------------------------- handrail

void test_handrail_measurement_5cm_off_is_rejected(void**) {
  Converged c(15.0);
  assert_int_equal(c.bad_health, 0);
  assert_true(c.f->handrail_map().valid);
  const double t = c.now_s() - 0.1;
  const Eigen::Vector3d offsets[] = {{0.05, 0, 0}, {0, 0.05, 0}, {0, 0, 0.05}, {0.03, -0.03, 0.03}};
  std::uint32_t rejected = 0;
  for (const Eigen::Vector3d& off : offsets) {
    auto m = std::make_unique<HandrailMeasurement>();
    assert_true(c.sim->detect(t, m.get(), off));
    const Snapshot before = snap(*c.f);
    const UpdateStatus st = c.f->add_handrail(*m);
    std::printf("  handrail %.0f mm off (%s): %s, %d of %d features gated\n", 1e3 * off.norm(),
                estimator::to_string(m->state), to_string(st), c.f->last_update().features_gated,
                c.f->last_update().features_gated + c.f->last_update().features_used);
    assert_int_equal(static_cast<int>(st), static_cast<int>(UpdateStatus::kRejectedGate));
    assert_true(same(before, snap(*c.f)));
    ++rejected;
  }
  assert_int_equal(
      c.f->counters().count(MeasurementKind::kHandrailEnds, UpdateStatus::kRejectedGate), rejected);
  // The same frame without the offset is accepted.
  auto good = std::make_unique<HandrailMeasurement>();
  assert_true(c.sim->detect(t, good.get()));
  assert_int_equal(static_cast<int>(c.f->add_handrail(*good)),
                   static_cast<int>(UpdateStatus::kAccepted));
}

// A detection biased by 1 cm for 3 frames in a row (a reflection, a
// neighbouring structure taken for part of the bar), across the bar (the
// wall normal, sideways) or along it. Such a frame passes the gate (the
// filter's own uncertainty relative to the bar between frames is about
// 3 mm): the estimate follows it, but by no more than the bias and a half,
// no map is dropped, and from 2 s after the last biased frame the error
// relative to the bar is what it is without the bias, within 1 mm.
struct BiasedRun {
  double across_max = 0.0, along_max = 0.0, after_max = 0.0;
  int bad_health = 0;
  std::uint32_t map_resets = 0;
};

BiasedRun run_with_biased_frames(const Eigen::Vector3d& off_h) {
  SimConfig sc;
  sc.seed = 21;
  sc.duration_s = 30.0;
  Sim sim(sc);
  std::vector<Event> events = sim.events();
  int biased = 0;
  double bias_from_s = 0.0, bias_to_s = 0.0;
  for (Event& e : events) {
    if (biased == 3 || e.kind != Event::kHandrail || e.capture_s < 15.0) continue;
    if (e.hr.state != HandrailState::kBothEnds) continue;
    if (!off_h.isZero()) {
      const Eigen::Vector3d off_cam = e.hr.T_cam_handrail.linear() * off_h;
      if (!sim.detect(e.capture_s, &e.hr, off_cam)) continue;
    }
    if (biased++ == 0) bias_from_s = e.capture_s;
    bias_to_s = e.arrival_s;
  }
  auto f = std::make_unique<LocalizationFilter>(locsim::sim_filter_config(sc));
  BiasedRun r;
  locsim::run_events(
      sim, events, *f,
      [&](int, double t) {
        if (!f->initialized()) return;
        r.bad_health += f->check() != Health::kOk;
        if (t < bias_from_s) return;
        const Eigen::Vector3d err =
            locsim::estimated_p_handrail_body(*f, sim) - sim.true_p_handrail_body(t);
        r.across_max = std::max(r.across_max, std::hypot(err.x(), err.y()));
        r.along_max = std::max(r.along_max, std::fabs(err.z()));
        if (t > bias_to_s + 2.0) r.after_max = std::max(r.after_max, err.norm());
      },
      [](const Event&, UpdateStatus) {}, [](int) { return false; });
  r.map_resets = f->counters().map_resets;
  return r;
}

void test_detection_biased_1cm_for_three_frames(void**) {
  const BiasedRun clean = run_with_biased_frames(Eigen::Vector3d::Zero());
  std::printf(
      "  no bias: error relative to the bar at most %.2f mm across, %.2f mm along; from 2 s "
      "after the third frame, at most %.2f mm\n",
      1e3 * clean.across_max, 1e3 * clean.along_max, 1e3 * clean.after_max);
  const Eigen::Vector3d offsets_handrail[] = {{0.01, 0, 0}, {0, 0.01, 0}, {0, 0, 0.01}};
  for (const Eigen::Vector3d& off_h : offsets_handrail) {
    const BiasedRun r = run_with_biased_frames(off_h);
    std::printf(
        "  1 cm off along handrail (%.0f, %.0f, %.0f) for 3 frames: at most %.2f mm across, "
        "%.2f mm along; from 2 s after, at most %.2f mm\n",
        1e2 * off_h.x(), 1e2 * off_h.y(), 1e2 * off_h.z(), 1e3 * r.across_max, 1e3 * r.along_max,
        1e3 * r.after_max);
    assert_int_equal(r.bad_health, 0);
    assert_int_equal(r.map_resets, 0);
    assert_true(std::max(r.across_max, r.along_max) < 0.015);
    assert_true(r.after_max < clean.after_max + 0.001);
  }
}

void test_persistent_offset_drops_and_rebuilds_the_map(void**) {
  Converged c(15.0);
  const int n = c.f->config().map_reset_after_rejections;
  for (int i = 0; i < n; ++i) {
    auto m = std::make_unique<HandrailMeasurement>();
    assert_true(c.sim->detect(c.now_s() - 0.1, m.get(), Eigen::Vector3d(0.05, 0, 0)));
    assert_int_equal(static_cast<int>(c.f->add_handrail(*m)),
                     static_cast<int>(UpdateStatus::kRejectedGate));
    assert_true(c.f->handrail_map().valid == (i < n - 1));
  }
  assert_int_equal(c.f->counters().map_resets, 1);
  // The next confident sightings build it again.
  UpdateStatus st = UpdateStatus::kRejectedInvalid;
  for (int i = 0; i < c.f->config().map_init_sightings; ++i) {
    auto m = std::make_unique<HandrailMeasurement>();
    assert_true(c.sim->detect(c.now_s() - 0.01 * (3 - i), m.get()));
    st = c.f->add_handrail(*m);
  }
  assert_int_equal(static_cast<int>(st), static_cast<int>(UpdateStatus::kMapInitialized));
  assert_true(c.f->handrail_map().valid);
}

// No end seen before there is a map: the sightings build a line map (its
// origin somewhere on the bar), which NE updates can use from then on; the
// first sighting only counts, the state untouched. Sightings with an end
// then count toward a map placed along the bar, each used as NE against the
// line meanwhile, and replace the line map when complete.
void test_no_end_sightings_build_a_line_map(void**) {
  Converged c(5.0);
  c.f->reset_handrail_map();
  const auto sighting = [&](double dt_s, HandrailState state) {
    auto m = std::make_unique<HandrailMeasurement>();
    assert_true(c.sim->detect(c.now_s() - dt_s, m.get()));
    if (state == HandrailState::kNoEnd) {
      // The detector cannot place an NE frame along the bar: its origin
      // slides with the part in view.
      m->T_cam_handrail = m->T_cam_handrail * Eigen::Translation3d(0.0, 0.0, 0.04 * dt_s / 0.01);
      for (int k = 0; k < m->num_features; ++k) {
        m->features[static_cast<std::size_t>(k)].p_handrail_m.z() -= 0.04 * dt_s / 0.01;
      }
    }
    m->state = state;
    return c.f->add_handrail(*m);
  };
  const Snapshot before = snap(*c.f);
  assert_int_equal(static_cast<int>(sighting(0.05, HandrailState::kNoEnd)),
                   static_cast<int>(UpdateStatus::kMapSighting));
  assert_true(same(before, snap(*c.f)));
  assert_int_equal(static_cast<int>(sighting(0.04, HandrailState::kNoEnd)),
                   static_cast<int>(UpdateStatus::kMapSighting));
  assert_int_equal(static_cast<int>(sighting(0.03, HandrailState::kNoEnd)),
                   static_cast<int>(UpdateStatus::kMapInitialized));
  assert_true(c.f->handrail_map().valid);
  assert_false(c.f->handrail_map().along_known);
  assert_int_equal(static_cast<int>(sighting(0.02, HandrailState::kNoEnd)),
                   static_cast<int>(UpdateStatus::kAccepted));
  // Ends seen: used as NE while they count, then the map with ends.
  assert_int_equal(static_cast<int>(sighting(0.015, HandrailState::kBothEnds)),
                   static_cast<int>(UpdateStatus::kAccepted));
  assert_int_equal(static_cast<int>(sighting(0.01, HandrailState::kBothEnds)),
                   static_cast<int>(UpdateStatus::kAccepted));
  assert_false(c.f->handrail_map().along_known);
  assert_int_equal(static_cast<int>(sighting(0.005, HandrailState::kBothEnds)),
                   static_cast<int>(UpdateStatus::kMapInitialized));
  assert_true(c.f->handrail_map().valid && c.f->handrail_map().along_known);
  assert_int_equal(c.f->counters().map_line_replaced, 1);
  assert_int_equal(static_cast<int>(sighting(0.0, HandrailState::kBothEnds)),
                   static_cast<int>(UpdateStatus::kAccepted));
  assert_int_equal(c.bad_health, 0);
  assert_true(c.f->check() == Health::kOk);
}
// ------------------------------------------------------------- bad input

void test_non_finite_and_malformed_input_is_rejected_untouched(void**) {
  Converged c(12.0);
  LocalizationFilter& f = *c.f;
  const Snapshot before = snap(f);
  const FilterCounters counters_before = f.counters();
  const std::int64_t now = f.time_us();

  // IMU.
  ImuSample s;
  s.t_us = now + 16000;
  s.omega_body_radps = Eigen::Vector3d(0, 0, kNaN);
  assert_int_equal(static_cast<int>(f.add_imu(s)), static_cast<int>(ImuStatus::kRejectedNotFinite));
  s.omega_body_radps.setZero();
  s.a_body_mps2 = Eigen::Vector3d(kInf, 0, 0);
  assert_int_equal(static_cast<int>(f.add_imu(s)), static_cast<int>(ImuStatus::kRejectedNotFinite));
  s.a_body_mps2 = Eigen::Vector3d(0, -kInf, 0);
  assert_int_equal(static_cast<int>(f.add_imu(s)), static_cast<int>(ImuStatus::kRejectedNotFinite));
  s.a_body_mps2 = Eigen::Vector3d(100.0, 0, 0);
  assert_int_equal(static_cast<int>(f.add_imu(s)),
                   static_cast<int>(ImuStatus::kRejectedOutOfRange));
  s.a_body_mps2.setZero();
  s.omega_body_radps = Eigen::Vector3d(0, 20.0, 0);
  assert_int_equal(static_cast<int>(f.add_imu(s)),
                   static_cast<int>(ImuStatus::kRejectedOutOfRange));
  s.omega_body_radps.setZero();
  s.t_us = now;  // a repeat of the newest time
  assert_int_equal(static_cast<int>(f.add_imu(s)),
                   static_cast<int>(ImuStatus::kRejectedOutOfOrder));
  s.t_us = now - 50000;
  assert_int_equal(static_cast<int>(f.add_imu(s)),
                   static_cast<int>(ImuStatus::kRejectedOutOfOrder));

  // GP poses.
  GpPose good;
  good.capture_time_us = now - 100000;
  const locsim::Truth tr = c.sim->truth(1e-6 * static_cast<double>(good.capture_time_us));
  good.p_world_body_m = tr.p;
  good.q_world_body = tr.q;
  good.cov = PoseCovariance::Identity() * 1e-3;
  const auto gp_status = [&](auto&& edit) {
    GpPose g = good;
    edit(g);
    return static_cast<int>(f.add_gp_pose(g));
  };
  const int kNotFinite = static_cast<int>(UpdateStatus::kRejectedNotFinite);
  const int kInvalid = static_cast<int>(UpdateStatus::kRejectedInvalid);
  assert_int_equal(gp_status([](GpPose& g) { g.p_world_body_m.x() = kNaN; }), kNotFinite);
  assert_int_equal(gp_status([](GpPose& g) { g.q_world_body.w() = kNaN; }), kNotFinite);
  assert_int_equal(gp_status([](GpPose& g) { g.cov(2, 4) = kInf; }), kNotFinite);
  assert_int_equal(gp_status([](GpPose& g) { g.q_world_body.coeffs() *= 1.1; }), kInvalid);
  assert_int_equal(gp_status([](GpPose& g) { g.cov(0, 1) = 1e-4; }), kInvalid);   // asymmetric
  assert_int_equal(gp_status([](GpPose& g) { g.cov(3, 3) = -1e-3; }), kInvalid);  // not PD
  assert_int_equal(gp_status([](GpPose& g) { g.cov.setZero(); }), kInvalid);
  assert_int_equal(gp_status([](GpPose& g) {
                     g.cov(0, 1) = g.cov(1, 0) = 2e-3;  // symmetric, indefinite
                   }),
                   kInvalid);

  // Handrail measurements.
  auto good_hr = std::make_unique<HandrailMeasurement>();
  assert_true(c.sim->detect(1e-6 * static_cast<double>(now) - 0.08, good_hr.get()));
  auto m = std::make_unique<HandrailMeasurement>();
  const auto hr_status = [&](auto&& edit) {
    *m = *good_hr;
    edit(*m);
    return static_cast<int>(f.add_handrail(*m));
  };
  assert_int_equal(hr_status([](HandrailMeasurement& h) { h.features[3].p_cam_m.y() = kNaN; }),
                   kNotFinite);
  assert_int_equal(
      hr_status([](HandrailMeasurement& h) { h.features[45].p_handrail_m.z() = kInf; }),
      kNotFinite);
  assert_int_equal(hr_status([](HandrailMeasurement& h) { h.T_cam_handrail(1, 3) = kNaN; }),
                   kNotFinite);
  assert_int_equal(hr_status([](HandrailMeasurement& h) { h.T_cam_handrail(0, 0) = kInf; }),
                   kNotFinite);
  assert_int_equal(hr_status([](HandrailMeasurement& h) { h.state = HandrailState::kNoHandrail; }),
                   kInvalid);
  assert_int_equal(
      hr_status([](HandrailMeasurement& h) { h.state = static_cast<HandrailState>(9); }), kInvalid);
  assert_int_equal(
      hr_status([](HandrailMeasurement& h) { h.num_features = kMaxInputFeatures + 1; }), kInvalid);
  assert_int_equal(hr_status([](HandrailMeasurement& h) { h.num_features = -1; }), kInvalid);
  assert_int_equal(hr_status([](HandrailMeasurement& h) { h.T_cam_handrail.linear() *= 1.01; }),
                   kInvalid);
  assert_int_equal(
      hr_status([](HandrailMeasurement& h) { h.features[0].kind = static_cast<FeatureKind>(7); }),
      kInvalid);
  assert_int_equal(hr_status([](HandrailMeasurement& h) { h.num_features = 2; }),
                   static_cast<int>(UpdateStatus::kRejectedTooFewFeatures));

  assert_true(same(before, snap(f)));
  const FilterCounters& k = f.counters();
  assert_int_equal(
      k.count(ImuStatus::kRejectedNotFinite) - counters_before.count(ImuStatus::kRejectedNotFinite),
      3);
  assert_int_equal(k.count(ImuStatus::kRejectedOutOfRange), 2);
  assert_int_equal(k.count(ImuStatus::kRejectedOutOfOrder), 2);
  assert_int_equal(k.count(MeasurementKind::kGpPose, UpdateStatus::kRejectedNotFinite), 3);
  assert_int_equal(k.count(MeasurementKind::kGpPose, UpdateStatus::kRejectedInvalid), 5);
  assert_int_equal(k.count(MeasurementKind::kHandrailEnds, UpdateStatus::kRejectedNotFinite), 4);
  assert_int_equal(k.count(MeasurementKind::kHandrailEnds, UpdateStatus::kRejectedInvalid), 6);
  // And the good ones still go through.
  assert_int_equal(static_cast<int>(f.add_handrail(*good_hr)),
                   static_cast<int>(UpdateStatus::kAccepted));
  assert_int_equal(static_cast<int>(f.add_gp_pose(good)),
                   static_cast<int>(UpdateStatus::kAccepted));
  assert_true(f.check() == Health::kOk);
}

// ------------------------------------------------------------- timing

void test_too_old_and_future_measurements(void**) {
  Converged c(12.0, /*handrail=*/false);
  LocalizationFilter& f = *c.f;
  const std::int64_t now = f.time_us();
  GpPose g;
  const auto at = [&](std::int64_t t_us) {
    g.capture_time_us = t_us;
    const locsim::Truth tr = c.sim->truth(1e-6 * static_cast<double>(t_us));
    g.p_world_body_m = tr.p;
    g.q_world_body = tr.q;
    g.cov = PoseCovariance::Identity() * 1e-3;
    return static_cast<int>(f.add_gp_pose(g));
  };
  const Snapshot before = snap(f);
  assert_int_equal(at(now - 1500000), static_cast<int>(UpdateStatus::kRejectedTooOld));
  assert_int_equal(at(now + 500000), static_cast<int>(UpdateStatus::kRejectedInFuture));
  assert_true(same(before, snap(f)));
  // Just past the newest sample (clock jitter): applied at the newest.
  assert_int_equal(at(now + 10000), static_cast<int>(UpdateStatus::kAccepted));
  // 0.9 s late is still inside the 1.0 s history.
  assert_int_equal(at(now - 900000), static_cast<int>(UpdateStatus::kAccepted));
  assert_true(f.check() == Health::kOk);
}

void test_before_initialisation(void**) {
  auto f = std::make_unique<LocalizationFilter>();
  GpPose g;
  g.capture_time_us = 1000;
  assert_int_equal(static_cast<int>(f->add_gp_pose(g)),
                   static_cast<int>(UpdateStatus::kRejectedNotInitialized));
  auto m = std::make_unique<HandrailMeasurement>();
  m->state = HandrailState::kBothEnds;
  assert_int_equal(static_cast<int>(f->add_handrail(*m)),
                   static_cast<int>(UpdateStatus::kRejectedNotInitialized));
  ImuSample s;
  for (int k = 0; k < 10; ++k) {
    s.t_us = 16000 * k;
    assert_int_equal(static_cast<int>(f->add_imu(s)), static_cast<int>(ImuStatus::kBuffered));
  }
  g.capture_time_us = 40000;  // between samples 2 and 3
  assert_int_equal(static_cast<int>(f->add_gp_pose(g)),
                   static_cast<int>(UpdateStatus::kInitialized));
  assert_true(f->initialized());
  assert_int_equal(f->time_us(), 16000 * 9);
  assert_true(f->check() == Health::kOk);
  // Measurements before the start are too old.
  g.capture_time_us = 20000;
  assert_int_equal(static_cast<int>(f->add_gp_pose(g)),
                   static_cast<int>(UpdateStatus::kRejectedTooOld));
}

void test_bad_configuration_rejects_everything(void**) {
  LocalizationConfig cfg;
  cfg.imu.accel_noise_mps2_rthz = kNaN;
  auto f = std::make_unique<LocalizationFilter>(cfg);
  assert_non_null(f->config_error());
  assert_string_equal(f->config_error(), "imu.accel_noise_mps2_rthz");
  ImuSample s;
  assert_int_equal(static_cast<int>(f->add_imu(s)),
                   static_cast<int>(ImuStatus::kRejectedBadConfig));
  GpPose g;
  assert_int_equal(static_cast<int>(f->add_gp_pose(g)),
                   static_cast<int>(UpdateStatus::kRejectedBadConfig));
  assert_true(f->check() == Health::kOk);
}

}  // namespace

int main() {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_imu_gap_half_second_is_bridged),
      cmocka_unit_test(test_imu_gap_of_two_seconds_is_lost_then_recovers),
      cmocka_unit_test(test_handrail_measurement_5cm_off_is_rejected),
      cmocka_unit_test(test_detection_biased_1cm_for_three_frames),
      cmocka_unit_test(test_persistent_offset_drops_and_rebuilds_the_map),
      cmocka_unit_test(test_no_end_sightings_build_a_line_map),
      cmocka_unit_test(test_non_finite_and_malformed_input_is_rejected_untouched),
      cmocka_unit_test(test_too_old_and_future_measurements),
      cmocka_unit_test(test_before_initialisation),
      cmocka_unit_test(test_bad_configuration_rejects_everything),
  };
  return cmocka_run_group_tests(tests, nullptr, nullptr);
}
