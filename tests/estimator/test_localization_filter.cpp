// The localization filter on the simulated granite-table world
// (test_localization_sim.hpp): convergence with handrail updates against
// GP-only, the along-bar uncertainty growing under NE measurements only, and
// late measurements applied at their capture time exactly as if on time.
// The state and covariance are checked after every step.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <vector>

#include "cmocka_cpp.hpp"
#include "estimator/localization/covariance_check.hpp"
#include "estimator/localization/localization_filter.hpp"
#include "test_localization_sim.hpp"

using namespace estimator::localization;
using locsim::Event;
using locsim::Sim;
using locsim::SimConfig;

namespace {

struct Errors {
  double sum_sq_rel = 0.0, max_rel = 0.0, sum_sq_world = 0.0, max_world = 0.0;
  double sum_sq_att = 0.0;
  int n = 0;
  int bad_health = 0;
  double rms_rel() const { return n ? std::sqrt(sum_sq_rel / n) : 0.0; }
  double rms_world() const { return n ? std::sqrt(sum_sq_world / n) : 0.0; }
  double rms_att_deg() const { return n ? std::sqrt(sum_sq_att / n) / locsim::kDeg : 0.0; }
};

// The true handrail pose off by a survey error: position_m along each axis,
// attitude_rad about the wall normal and the bar.
HandrailMap survey_of(const Sim& sim, double position_m, double attitude_rad, double sigma_m,
                      double sigma_rad) {
  HandrailMap m;
  m.T_world_handrail = sim.T_world_handrail();
  m.T_world_handrail.translation() += Eigen::Vector3d::Constant(position_m);
  m.T_world_handrail.linear() =
      Eigen::AngleAxisd(attitude_rad, Eigen::Vector3d(1.0, 0.0, 1.0).normalized()) *
      m.T_world_handrail.linear();
  m.position_sigma_m = sigma_m;
  m.attitude_sigma_rad = sigma_rad;
  return m;
}

// Runs a scenario; errors are collected after t_settle_s. With survey_error
// (position m, attitude rad, both as survey_of) the filter is given the
// handrail's surveyed pose with that error and a survey sigma of 2 mm and
// 0.1 deg.
Errors run_scenario(const SimConfig& sc, double t_settle_s, LocalizationFilter* out = nullptr,
                    const Eigen::Vector2d* survey_error = nullptr) {
  Sim sim(sc);
  auto f = std::make_unique<LocalizationFilter>(locsim::sim_filter_config(sc));
  if (survey_error) {
    assert_int_equal(static_cast<int>(f->set_handrail_survey(survey_of(
                         sim, survey_error->x(), survey_error->y(), 0.002, 0.1 * locsim::kDeg))),
                     static_cast<int>(UpdateStatus::kAccepted));
  }
  Errors e;
  locsim::run(
      sim, *f,
      [&](int, double t) {
        if (!f->initialized()) return;
        if (f->check() != Health::kOk) ++e.bad_health;
        if (t < t_settle_s) return;
        const locsim::Truth tr = sim.truth(t);
        const double rel =
            (locsim::estimated_p_handrail_body(*f, sim) - sim.true_p_handrail_body(t)).norm();
        const double world = (f->state().p_world_body_m - tr.p).norm();
        const HandrailMap map = f->handrail_map();
        const Eigen::Matrix3d R_map =
            map.valid ? map.T_world_handrail.rotation() : sim.T_world_handrail().rotation();
        const Eigen::Quaterniond q_rel_est(R_map.transpose() *
                                           f->state().q_world_body.toRotationMatrix());
        const Eigen::Quaterniond q_rel_true(sim.T_world_handrail().linear().transpose() *
                                            tr.q.toRotationMatrix());
        const double att = q_rel_est.angularDistance(q_rel_true);
        e.sum_sq_rel += rel * rel;
        e.max_rel = std::max(e.max_rel, rel);
        e.sum_sq_world += world * world;
        e.max_world = std::max(e.max_world, world);
        e.sum_sq_att += att * att;
        ++e.n;
      },
      [](const Event&, UpdateStatus) {});
  if (out) *out = *f;
  return e;
}

void test_converges_with_handrail_updates(void**) {
  SimConfig sc;
  sc.seed = 11;
  auto f = std::make_unique<LocalizationFilter>();
  const Errors e = run_scenario(sc, 10.0, f.get());
  const FilterCounters& c = f->counters();
  std::printf(
      "  with handrail: relative position RMS %.2f mm (max %.2f), attitude RMS %.3f deg; world "
      "RMS %.1f mm; handrail accepted %u rejected %u, GP accepted %u rejected %u\n",
      1e3 * e.rms_rel(), 1e3 * e.max_rel, e.rms_att_deg(), 1e3 * e.rms_world(),
      c.count(MeasurementKind::kHandrailEnds, UpdateStatus::kAccepted),
      c.rejected(MeasurementKind::kHandrailEnds),
      c.count(MeasurementKind::kGpPose, UpdateStatus::kAccepted),
      c.rejected(MeasurementKind::kGpPose));
  assert_int_equal(e.bad_health, 0);
  assert_true(f->handrail_map().valid);
  assert_true(e.rms_rel() < 0.005);
  assert_true(e.max_rel < 0.012);
  assert_true(e.rms_att_deg() < 0.3);
  assert_true(c.count(MeasurementKind::kHandrailEnds, UpdateStatus::kAccepted) > 150);
}

// With the handrail's surveyed pose the handrail places the robot in the
// world: the world error falls from the GP's bias (28 mm RMS with a map
// from sightings, test above) to a few mm. The survey (2 mm sigma) is a
// prior in the state, which the GP's poses refine: the simulated GP's
// error is a slow bias of up to 3 cm that the filter takes for white noise,
// so over 10 s its poses pull the map by a fraction of that bias.
void test_surveyed_map_gives_the_world_pose(void**) {
  SimConfig sc;
  sc.seed = 11;
  auto f = std::make_unique<LocalizationFilter>();
  const Eigen::Vector2d survey_error(0.001, 0.05 * locsim::kDeg);
  const Errors e = run_scenario(sc, 10.0, f.get(), &survey_error);
  const FilterCounters& c = f->counters();
  std::printf(
      "  surveyed map (off by 1 mm per axis, 0.05 deg): world RMS %.2f mm (max %.2f), relative "
      "to the true handrail's frame through the survey %.2f mm; handrail accepted %u rejected "
      "%u\n",
      1e3 * e.rms_world(), 1e3 * e.max_world, 1e3 * e.rms_rel(),
      c.count(MeasurementKind::kHandrailEnds, UpdateStatus::kAccepted),
      c.rejected(MeasurementKind::kHandrailEnds));
  assert_int_equal(e.bad_health, 0);
  assert_true(f->handrail_map().surveyed);
  assert_int_equal(c.count(MeasurementKind::kHandrailEnds, UpdateStatus::kMapSighting), 0);
  assert_true(c.count(MeasurementKind::kHandrailEnds, UpdateStatus::kAccepted) > 150);
  assert_true(e.rms_world() < 0.010);
  assert_true(e.max_world < 0.020);
}

// A survey is checked before it is taken, and stays the map wherever a map
// from sightings would be dropped.
void test_survey_is_checked_and_kept(void**) {
  SimConfig sc;
  Sim sim(sc);
  auto f = std::make_unique<LocalizationFilter>();
  HandrailMap bad = survey_of(sim, 0.0, 0.0, 0.002, 0.001);
  bad.T_world_handrail.translation().x() = std::nan("");
  assert_int_equal(static_cast<int>(f->set_handrail_survey(bad)),
                   static_cast<int>(UpdateStatus::kRejectedNotFinite));
  bad = survey_of(sim, 0.0, 0.0, 0.002, 0.001);
  bad.T_world_handrail.linear() *= 1.01;  // not a rotation
  assert_int_equal(static_cast<int>(f->set_handrail_survey(bad)),
                   static_cast<int>(UpdateStatus::kRejectedInvalid));
  bad = survey_of(sim, 0.0, 0.0, -0.002, 0.001);
  assert_int_equal(static_cast<int>(f->set_handrail_survey(bad)),
                   static_cast<int>(UpdateStatus::kRejectedInvalid));
  assert_false(f->handrail_map().valid);
  const HandrailMap good = survey_of(sim, 0.0, 0.0, 0.002, 0.001);
  assert_int_equal(static_cast<int>(f->set_handrail_survey(good)),
                   static_cast<int>(UpdateStatus::kAccepted));
  assert_true(f->handrail_map().valid && f->handrail_map().surveyed);
  f->reset_handrail_map();
  assert_true(f->handrail_map().valid && f->handrail_map().surveyed);
  f->reset();
  assert_true(f->handrail_map().valid && f->handrail_map().surveyed);
  assert_true(f->handrail_map().T_world_handrail.isApprox(good.T_world_handrail));
  f->clear_handrail_survey();
  assert_false(f->handrail_map().valid);
}

void test_gp_only_stays_at_gp_bias(void**) {
  SimConfig sc;
  sc.seed = 11;
  sc.handrail = false;
  const Errors e = run_scenario(sc, 10.0);
  std::printf("  GP only: relative position RMS %.1f mm (max %.1f), attitude RMS %.3f deg\n",
              1e3 * e.rms_rel(), 1e3 * e.max_rel, e.rms_att_deg());
  assert_int_equal(e.bad_health, 0);
  // The GP's bias (3 cm amplitude) shows through: no better than about 1 cm.
  assert_true(e.rms_rel() > 0.01);
  assert_true(e.rms_rel() < 0.06);
}

// The robot approaches the bar from where both ends are in view to where
// none is (NE); the GP stops as it arrives. With only NE measurements the
// position along the bar is unobserved: its variance relative to the
// handrail grows (the velocity random walk integrates) tenfold and more,
// while across the bar it stays at a few mm. It may fall a little on an
// update: part of it is the map's attitude times the robot's distance from
// the bar, which the NE updates do observe.
void test_along_bar_uncertainty_grows_with_no_end_only(void**) {
  SimConfig sc;
  sc.seed = 5;
  sc.duration_s = 45.0;
  sc.traj.x_start = 1.0;
  sc.traj.x_end = 0.62;
  sc.traj.t_move_start = 10.0;
  sc.traj.t_move_end = 16.0;
  sc.traj.ax = 0.02;
  sc.gp_stop_s = 18.0;
  Sim sim(sc);
  auto f = std::make_unique<LocalizationFilter>(locsim::sim_filter_config(sc));
  double along_at_20 = 0.0, along_at_end = 0.0, max_across_sigma = 0.0, max_across_err = 0.0;
  double prev_along = 0.0, max_decrease = 0.0;
  int along_decreases = 0, bad_health = 0, ne_after_20 = 0, other_after_20 = 0;
  locsim::run(
      sim, *f,
      [&](int, double t) {
        if (!f->initialized()) return;
        if (f->check() != Health::kOk) ++bad_health;
        if (t < 20.0 || !f->handrail_map().valid) return;
        // The covariance relative to the handrail, in its frame.
        const Eigen::Matrix3d P = f->estimate().handrail_position_cov;
        const double along = std::sqrt(P(2, 2));
        const double across = std::sqrt(std::max(P(0, 0), P(1, 1)));
        const Eigen::Vector3d err =
            locsim::estimated_p_handrail_body(*f, sim) - sim.true_p_handrail_body(t);
        if (along_at_20 == 0.0) along_at_20 = along;
        if (along < prev_along) {
          ++along_decreases;
          max_decrease = std::max(max_decrease, 1.0 - along / prev_along);
        }
        prev_along = along;
        along_at_end = along;
        max_across_sigma = std::max(max_across_sigma, across);
        max_across_err = std::max(max_across_err, std::hypot(err.x(), err.y()));
      },
      [&](const Event& e, UpdateStatus st) {
        if (e.capture_s < 20.0 || e.kind != Event::kHandrail) return;
        if (e.hr.state == estimator::HandrailState::kNoEnd && st == UpdateStatus::kAccepted) {
          ++ne_after_20;
        } else {
          ++other_after_20;
        }
      });
  std::printf(
      "  NE only from t = 20 s: along-bar sigma %.1f mm -> %.1f mm at %.0f s; across-bar sigma "
      "<= %.2f mm, error <= %.2f mm; %d NE updates accepted; along-bar sigma fell %d times, by "
      "%.2f %% at most\n",
      1e3 * along_at_20, 1e3 * along_at_end, sc.duration_s, 1e3 * max_across_sigma,
      1e3 * max_across_err, ne_after_20, along_decreases, 100.0 * max_decrease);
  assert_int_equal(bad_health, 0);
  assert_int_equal(other_after_20, 0);  // every measurement then is an accepted NE
  assert_true(ne_after_20 > 100);
  assert_true(along_at_end > 10.0 * along_at_20);  // nothing pins it
  assert_true(max_across_sigma < 0.005);
  assert_true(max_across_err < 0.01);
}

// The same measurements delivered late (as they come) and on time (each
// right after the first IMU sample at or past its capture): the history and
// re-propagation make the two filters end in the same state, to rounding.
void test_late_measurements_equal_on_time(void**) {
  SimConfig sc;
  sc.seed = 3;
  sc.duration_s = 12.0;
  Sim sim(sc);
  const LocalizationConfig cfg = locsim::sim_filter_config(sc);
  auto late = std::make_unique<LocalizationFilter>(cfg);
  auto on_time = std::make_unique<LocalizationFilter>(cfg);
  locsim::run(
      sim, *late, [](int, double) {}, [](const Event&, UpdateStatus) {});

  std::vector<const Event*> by_capture;
  for (const Event& e : sim.events()) by_capture.push_back(&e);
  std::sort(by_capture.begin(), by_capture.end(), [](const Event* a, const Event* b) {
    return a->capture_s < b->capture_s || (a->capture_s == b->capture_s && a->order < b->order);
  });
  std::size_t next = 0;
  for (const ImuSample& s : sim.imu()) {
    on_time->add_imu(s);
    while (next < by_capture.size() && locsim::to_us(by_capture[next]->capture_s) <= s.t_us) {
      const Event& e = *by_capture[next++];
      if (e.kind == Event::kGp) {
        on_time->add_gp_pose(e.gp);
      } else {
        on_time->add_handrail(e.hr);
      }
    }
  }
  const FilterCounters& a = late->counters();
  const FilterCounters& b = on_time->counters();
  std::printf("  late: %u GP, %u handrail accepted; on time: %u GP, %u handrail\n",
              a.count(MeasurementKind::kGpPose, UpdateStatus::kAccepted),
              a.count(MeasurementKind::kHandrailEnds, UpdateStatus::kAccepted),
              b.count(MeasurementKind::kGpPose, UpdateStatus::kAccepted),
              b.count(MeasurementKind::kHandrailEnds, UpdateStatus::kAccepted));
  assert_true(a.count(MeasurementKind::kHandrailEnds, UpdateStatus::kAccepted) > 40);
  assert_int_equal(a.count(MeasurementKind::kGpPose, UpdateStatus::kAccepted),
                   b.count(MeasurementKind::kGpPose, UpdateStatus::kAccepted));
  assert_int_equal(a.count(MeasurementKind::kHandrailEnds, UpdateStatus::kAccepted),
                   b.count(MeasurementKind::kHandrailEnds, UpdateStatus::kAccepted));
  const double dp = (late->state().p_world_body_m - on_time->state().p_world_body_m).norm();
  const double dq = late->state().q_world_body.angularDistance(on_time->state().q_world_body);
  const double dP = (late->covariance() - on_time->covariance()).cwiseAbs().maxCoeff() /
                    on_time->covariance().cwiseAbs().maxCoeff();
  std::printf("  late vs on time: |dp| %.3g m, attitude %.3g rad, covariance %.3g (relative)\n", dp,
              dq, dP);
  assert_true(dp < 1e-9);
  assert_true(dq < 1e-9);
  assert_true(dP < 1e-9);
  assert_int_equal(a.replay_rejections, 0);
}

}  // namespace

int main() {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_converges_with_handrail_updates),
      cmocka_unit_test(test_surveyed_map_gives_the_world_pose),
      cmocka_unit_test(test_survey_is_checked_and_kept),
      cmocka_unit_test(test_gp_only_stays_at_gp_bias),
      cmocka_unit_test(test_along_bar_uncertainty_grows_with_no_end_only),
      cmocka_unit_test(test_late_measurements_equal_on_time),
  };
  return cmocka_run_group_tests(tests, nullptr, nullptr);
}
