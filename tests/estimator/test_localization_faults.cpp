// Faults with defined outcomes, one test each, on the simulated world
// (test_localization_sim.hpp):
//   IMU samples missing for 0.5 s  -> bridged (GAP_BRIDGED): propagated in
//                                     sub-steps with extra noise, covariance
//                                     grows, the estimate stays on track;
//   missing for 2 s                -> GAP_LOST: held, covariance inflated,
//                                     flagged lost until an absolute fix;
//   a handrail measurement 5 cm off -> REJECTED_GATE, counted, state untouched;
//   ten of them in a row           -> the map is dropped and built again;
//   the GP pose jumping 20 cm      -> GP only: REJECTED_GATE, REJECTED_JUMP,
//                                     then RELOCALIZED (the rule); with the handrail
//                                     holding: rejected every time; a single
//                                     glitch: rejected once, nothing moves;
//   an IMU glitch that sends the filter away from every GP pose at once
//                                  -> after reinitialize_after rejections it
//                                     starts again from the GP (RELOCALIZED);
//   NaN, infinity or malformed input of any kind -> rejected, counted, the
//                                     state untouched (bit for bit);
//   too old, from the future, bad configuration -> their statuses.
// The state and covariance are checked after every step of every run.
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <vector>

#include "cmocka_cpp.hpp"
#include "estimator/localization/localization_filter.hpp"
#include "test_localization_sim.hpp"

using namespace estimator::localization;
using estimator::HandrailState;
using locsim::Event;
using locsim::Sim;
using locsim::SimConfig;

namespace {

const double kNaN = std::numeric_limits<double>::quiet_NaN();
const double kInf = std::numeric_limits<double>::infinity();

struct Snapshot {
  NominalState x;
  Covariance P;
  std::int64_t t_us;
  bool map_valid;
};

Snapshot snap(const LocalizationFilter& f) {
  return {f.state(), f.covariance(), f.time_us(), f.handrail_map().valid};
}

bool same(const Snapshot& a, const Snapshot& b) {
  return a.x.p_world_body_m == b.x.p_world_body_m && a.x.v_world_body_mps == b.x.v_world_body_mps &&
         a.x.q_world_body.coeffs() == b.x.q_world_body.coeffs() &&
         a.x.gyro_bias_radps == b.x.gyro_bias_radps && a.x.accel_bias_mps2 == b.x.accel_bias_mps2 &&
         a.P == b.P && a.t_us == b.t_us && a.map_valid == b.map_valid;
}

double rel_error(const LocalizationFilter& f, const Sim& sim, double t) {
  return (locsim::estimated_p_handrail_body(f, sim) - sim.true_p_handrail_body(t)).norm();
}

// A filter that has converged on the handrail (BE) for `seconds`.
struct Converged {
  SimConfig sc;
  std::unique_ptr<Sim> sim;
  std::unique_ptr<LocalizationFilter> f;
  int bad_health = 0;
  explicit Converged(double seconds, bool handrail = true, std::uint64_t seed = 21) {
    sc.seed = seed;
    sc.duration_s = 60.0;
    sc.handrail = handrail;
    sim = std::make_unique<Sim>(sc);
    f = std::make_unique<LocalizationFilter>(locsim::sim_filter_config(sc));
    locsim::run(
        *sim, *f, [&](int, double) { bad_health += f->initialized() && f->check() != Health::kOk; },
        [](const Event&, UpdateStatus) {}, locsim::sample_at(*sim, seconds) + 1);
  }
  double now_s() const { return 1e-6 * static_cast<double>(f->time_us()); }
};

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
        const double sigma = std::sqrt(f->covariance().block<3, 3>(kPos, kPos).trace());
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

void test_no_end_before_a_map_is_no_map(void**) {
  Converged c(5.0);
  c.f->reset_handrail_map();
  auto m = std::make_unique<HandrailMeasurement>();
  assert_true(c.sim->detect(c.now_s() - 0.05, m.get()));
  m->state = HandrailState::kNoEnd;
  const Snapshot before = snap(*c.f);
  assert_int_equal(static_cast<int>(c.f->add_handrail(*m)), static_cast<int>(UpdateStatus::kNoMap));
  assert_true(same(before, snap(*c.f)));
}

// ------------------------------------------------------------- GP jumps

// GP events with a 20 cm jump for captures in [from, to).
std::vector<Event> jumped(const Sim& sim, double from, double to) {
  std::vector<Event> ev = sim.events();
  for (Event& e : ev) {
    if (e.kind == Event::kGp && e.capture_s >= from && e.capture_s < to) {
      e.gp.p_world_body_m += Eigen::Vector3d(0.12, -0.16, 0.0);  // 20 cm
    }
  }
  return ev;
}

void test_gp_jump_relocalizes_when_gp_only(void**) {
  SimConfig sc;
  sc.seed = 41;
  sc.duration_s = 30.0;
  sc.handrail = false;
  Sim sim(sc);
  auto f = std::make_unique<LocalizationFilter>(locsim::sim_filter_config(sc));
  const std::vector<Event> ev = jumped(sim, 15.0, 1e9);
  std::vector<UpdateStatus> after_jump;
  double max_err_to_new_frame = 0.0, max_err_any = 0.0;
  int bad_health = 0;
  locsim::run_events(
      sim, ev, *f,
      [&](int, double t) {
        if (!f->initialized()) return;
        bad_health += f->check() != Health::kOk;
        const locsim::Truth tr = sim.truth(t);
        const double to_old = (f->state().p_world_body_m - tr.p).norm();
        const double to_new =
            (f->state().p_world_body_m - tr.p - Eigen::Vector3d(0.12, -0.16, 0.0)).norm();
        max_err_any = std::max(max_err_any, std::min(to_old, to_new));
        if (t > 22.0) max_err_to_new_frame = std::max(max_err_to_new_frame, to_new);
      },
      [&](const Event& e, UpdateStatus st) {
        if (e.kind == Event::kGp && e.capture_s >= 15.0) after_jump.push_back(st);
      },
      [](int) { return false; });
  std::printf(
      "  GP jump of 20 cm, GP only: %s, %s, %s, then %s; later error to the new frame "
      "<= %.1f mm\n",
      to_string(after_jump[0]), to_string(after_jump[1]), to_string(after_jump[2]),
      to_string(after_jump[3]), 1e3 * max_err_to_new_frame);
  assert_int_equal(bad_health, 0);
  assert_int_equal(static_cast<int>(after_jump[0]), static_cast<int>(UpdateStatus::kRejectedGate));
  assert_int_equal(static_cast<int>(after_jump[1]), static_cast<int>(UpdateStatus::kRejectedJump));
  assert_int_equal(static_cast<int>(after_jump[2]), static_cast<int>(UpdateStatus::kRelocalized));
  for (std::size_t i = 3; i < after_jump.size(); ++i) {
    assert_int_equal(static_cast<int>(after_jump[i]), static_cast<int>(UpdateStatus::kAccepted));
  }
  assert_int_equal(f->counters().count(MeasurementKind::kGpPose, UpdateStatus::kRelocalized), 1);
  assert_true(max_err_to_new_frame < 0.06);  // at the GP's bias level, in its new frame
  assert_true(max_err_any < 0.08);           // never anywhere in between, never diverging
}

// An IMU glitch (5 m/s^2 more along y for 0.3 s, within what the input
// checks pass) leaves the filter 1.5 m/s off: it runs away from every GP
// pose at once, so their offsets from it never agree and the jump rule
// never moves it (seen in the HIL perch: 10 m off after 15 s, every fix
// gated). The divergence rule starts it again from the GP pose after
// reinitialize_after rejections in a row; with the rule off it is still
// metres off at the end.
struct GlitchRun {
  double final_error_m = 0.0, worst_after_25s_m = 0.0;
  std::uint32_t reinitializations = 0;
  int bad_health = 0;
};

GlitchRun run_with_imu_glitch(int reinitialize_after) {
  SimConfig sc;
  sc.seed = 43;
  sc.duration_s = 35.0;
  sc.handrail = false;
  Sim sim(sc);
  LocalizationConfig cfg = locsim::sim_filter_config(sc);
  cfg.reinitialize_after = reinitialize_after;
  auto f = std::make_unique<LocalizationFilter>(cfg);
  GlitchRun r;
  const int from = locsim::sample_at(sim, 15.0), to = locsim::sample_at(sim, 15.3);
  locsim::run_events(
      sim, sim.events(), *f,
      [&](int, double t) {
        if (!f->initialized()) return;
        r.bad_health += f->check() != Health::kOk;
        const double err = (f->state().p_world_body_m - sim.truth(t).p).norm();
        if (t > 25.0) r.worst_after_25s_m = std::max(r.worst_after_25s_m, err);
        r.final_error_m = err;
      },
      [](const Event&, UpdateStatus) {},
      [&](int k) {
        if (k < from || k >= to) return false;
        ImuSample s = sim.imu()[static_cast<std::size_t>(k)];
        s.a_body_mps2.y() += 5.0;
        f->add_imu(s);
        return true;  // the glitched sample in its place
      });
  r.reinitializations = f->counters().reinitializations;
  return r;
}

void test_imu_glitch_divergence_reinitializes_from_gp(void**) {
  const GlitchRun with = run_with_imu_glitch(LocalizationConfig{}.reinitialize_after);
  const GlitchRun without = run_with_imu_glitch(100);
  std::printf(
      "  IMU glitch, GP only: %u reinitialisation(s), error after 25 s <= %.1f mm, at the end "
      "%.1f mm; without the rule %.2f m at the end\n",
      with.reinitializations, 1e3 * with.worst_after_25s_m, 1e3 * with.final_error_m,
      without.final_error_m);
  assert_int_equal(with.bad_health, 0);
  assert_true(with.reinitializations >= 1);
  assert_true(with.worst_after_25s_m < 0.08);  // back at the GP's bias level
  assert_int_equal(static_cast<int>(without.reinitializations), 0);
  assert_true(without.final_error_m > 1.0);
}

void test_gp_jump_rejected_while_handrail_holds(void**) {
  SimConfig sc;
  sc.seed = 42;
  sc.duration_s = 35.0;
  Sim sim(sc);
  auto f = std::make_unique<LocalizationFilter>(locsim::sim_filter_config(sc));
  const std::vector<Event> ev = jumped(sim, 15.0, 1e9);
  int rejected = 0, other = 0, bad_health = 0;
  double max_rel = 0.0;
  locsim::run_events(
      sim, ev, *f,
      [&](int, double t) {
        if (!f->initialized()) return;
        bad_health += f->check() != Health::kOk;
        if (t > 15.0) max_rel = std::max(max_rel, rel_error(*f, sim, t));
      },
      [&](const Event& e, UpdateStatus st) {
        if (e.kind != Event::kGp || e.capture_s < 15.0) return;
        if (st == UpdateStatus::kRejectedGate || st == UpdateStatus::kRejectedJump) {
          ++rejected;
        } else {
          ++other;
        }
      },
      [](int) { return false; });
  std::printf(
      "  GP jump of 20 cm, handrail holding: %d rejected, %d otherwise; relative error "
      "<= %.2f mm\n",
      rejected, other, 1e3 * max_rel);
  assert_int_equal(bad_health, 0);
  assert_int_equal(other, 0);
  assert_true(rejected >= 25);
  assert_int_equal(f->counters().count(MeasurementKind::kGpPose, UpdateStatus::kRelocalized), 0);
  assert_true(max_rel < 0.008);
}

void test_single_gp_glitch_changes_nothing(void**) {
  Converged c(15.0, /*handrail=*/false);
  GpPose g;
  g.capture_time_us = c.f->time_us() - 200000;
  const locsim::Truth tr = c.sim->truth(1e-6 * static_cast<double>(g.capture_time_us));
  g.p_world_body_m = tr.p + Eigen::Vector3d(0.0, 0.2, 0.0);
  g.q_world_body = tr.q;
  g.cov = PoseCovariance::Identity() * 0.03 * 0.03;
  g.cov.bottomRightCorner<3, 3>() = Eigen::Matrix3d::Identity() * 0.026 * 0.026;
  const Snapshot before = snap(*c.f);
  assert_int_equal(static_cast<int>(c.f->add_gp_pose(g)),
                   static_cast<int>(UpdateStatus::kRejectedGate));
  assert_true(same(before, snap(*c.f)));
  // The next pose is back where it was: accepted; no relocalisation.
  g.p_world_body_m = tr.p;
  g.capture_time_us += 10000;
  assert_int_equal(static_cast<int>(c.f->add_gp_pose(g)),
                   static_cast<int>(UpdateStatus::kAccepted));
  assert_int_equal(c.f->counters().count(MeasurementKind::kGpPose, UpdateStatus::kRelocalized), 0);
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
      cmocka_unit_test(test_persistent_offset_drops_and_rebuilds_the_map),
      cmocka_unit_test(test_no_end_before_a_map_is_no_map),
      cmocka_unit_test(test_gp_jump_relocalizes_when_gp_only),
      cmocka_unit_test(test_imu_glitch_divergence_reinitializes_from_gp),
      cmocka_unit_test(test_gp_jump_rejected_while_handrail_holds),
      cmocka_unit_test(test_single_gp_glitch_changes_nothing),
      cmocka_unit_test(test_non_finite_and_malformed_input_is_rejected_untouched),
      cmocka_unit_test(test_too_old_and_future_measurements),
      cmocka_unit_test(test_before_initialisation),
      cmocka_unit_test(test_bad_configuration_rejects_everything),
  };
  return cmocka_run_group_tests(tests, nullptr, nullptr);
}
