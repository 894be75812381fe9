// Proof that the localization filter allocates nothing per step: every
// operator new and (outside AddressSanitizer) every malloc on the test's
// thread is counted while armed, over thousands of IMU samples and hundreds
// of GP and handrail updates down every path: initialisation, late updates
// with re-propagation, the map built from sightings (and a line map from
// sightings with no end), BE, OE and NE updates, a bridged IMU gap and a
// lost one, gate rejections, a GP jump and its relocalisation, and
// non-finite input. The simulated world is built before counting starts.
#include <limits>
#include <memory>
#include <vector>

#include "allocation_counter.hpp"
#include "cmocka_cpp.hpp"
#include "estimator/localization/localization_filter.hpp"
#include "test_localization_sim.hpp"

using namespace estimator::localization;
using locsim::Event;
using locsim::Sim;
using locsim::SimConfig;

namespace {

void test_counter_counts(void**) {
  alloc_counter::arm();
  std::vector<int>* v = new std::vector<int>(10);
  const long n = alloc_counter::disarm();
  delete v;
  assert_true(n >= 2);
}

void test_no_allocation_over_thousands_of_steps(void**) {
  // An approach from both ends in view to none (BE, OE, NE), a 0.5 s and a
  // 2 s IMU gap; then GP only with a 20 cm jump.
  SimConfig a;
  a.seed = 77;
  a.duration_s = 40.0;
  a.traj.x_end = 0.62;
  a.traj.t_move_start = 12.0;
  a.traj.t_move_end = 18.0;
  Sim sim_a(a);
  SimConfig b;
  b.seed = 78;
  b.duration_s = 25.0;
  b.handrail = false;
  Sim sim_b(b);
  std::vector<Event> events_b = sim_b.events();
  for (Event& e : events_b) {
    if (e.kind == Event::kGp && e.capture_s > 12.0) e.gp.p_world_body_m.x() += 0.2;
  }
  auto bad = std::make_unique<HandrailMeasurement>();
  assert_true(sim_a.detect(5.0, bad.get(), Eigen::Vector3d(0.05, 0.0, 0.0)));
  auto nan_hr = std::make_unique<HandrailMeasurement>(*bad);
  nan_hr->features[2].p_cam_m.x() = std::numeric_limits<double>::quiet_NaN();
  auto fa = std::make_unique<LocalizationFilter>(locsim::sim_filter_config(a));
  auto fb = std::make_unique<LocalizationFilter>(locsim::sim_filter_config(b));
  const int gap1 = locsim::sample_at(sim_a, 8.0), gap2 = locsim::sample_at(sim_a, 30.0);
  const int forget_map = locsim::sample_at(sim_a, 22.0);  // then NE only: a line map
  ImuSample nan_imu;
  nan_imu.a_body_mps2.x() = std::numeric_limits<double>::infinity();

  alloc_counter::arm();
  int steps = 0, healthy = 0;
  locsim::run_events(
      sim_a, sim_a.events(), *fa,
      [&](int k, double) {
        ++steps;
        healthy += fa->check() == Health::kOk;
        if (k == forget_map) fa->reset_handrail_map();
        if (k == gap1 + 100) {
          bad->capture_time_us = fa->time_us() - 50000;
          fa->add_handrail(*bad);
          nan_hr->capture_time_us = bad->capture_time_us;
          fa->add_handrail(*nan_hr);
          nan_imu.t_us = fa->time_us() + 1000;
          fa->add_imu(nan_imu);
        }
      },
      [](const Event&, UpdateStatus) {},
      [&](int k) { return (k >= gap1 && k < gap1 + 31) || (k >= gap2 && k < gap2 + 125); });
  locsim::run_events(
      sim_b, events_b, *fb,
      [&](int, double) {
        ++steps;
        healthy += fb->check() == Health::kOk;
      },
      [](const Event&, UpdateStatus) {}, [](int) { return false; });
  const long allocations = alloc_counter::disarm();

  if (allocations != 0) print_error("%ld allocations over %d steps\n", allocations, steps);
  assert_int_equal(allocations, 0);
  assert_int_equal(healthy, steps);
  // Every path was taken.
  const FilterCounters& ca = fa->counters();
  const FilterCounters& cb = fb->counters();
  assert_true(ca.count(ImuStatus::kGapBridged) == 1);
  assert_true(ca.count(ImuStatus::kGapLost) == 1);
  assert_true(ca.count(ImuStatus::kRejectedNotFinite) == 1);
  assert_true(ca.count(MeasurementKind::kHandrailEnds, UpdateStatus::kMapInitialized) >= 1);
  assert_true(ca.count(MeasurementKind::kHandrailEnds, UpdateStatus::kAccepted) > 50);
  assert_true(ca.count(MeasurementKind::kHandrailNoEnd, UpdateStatus::kAccepted) > 50);
  assert_true(ca.count(MeasurementKind::kHandrailNoEnd, UpdateStatus::kMapInitialized) >= 1);
  assert_true(ca.count(MeasurementKind::kHandrailEnds, UpdateStatus::kRejectedGate) >= 1);
  assert_true(ca.count(MeasurementKind::kHandrailEnds, UpdateStatus::kRejectedNotFinite) == 1);
  assert_true(ca.count(MeasurementKind::kGpPose, UpdateStatus::kAccepted) > 20);
  assert_true(cb.count(MeasurementKind::kGpPose, UpdateStatus::kRelocalized) == 1);
  assert_true(steps > 4000);
}

}  // namespace

int main() {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_counter_counts),
      cmocka_unit_test(test_no_allocation_over_thousands_of_steps),
  };
  return cmocka_run_group_tests(tests, nullptr, nullptr);
}
