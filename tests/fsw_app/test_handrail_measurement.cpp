// A handrail estimate as the filter's measurement
// (fsw_app/handrail_measurement.hpp) and the bar's length learned from BE
// estimates (fsw_app/bar_length_tally.hpp). The OE centre is half the
// learned length from the seen end, and an OE estimate with no length known
// is used as NE; the wall features sit as far out either side of the bar as
// the camera sees, and still in view close up.
#include <cmath>
#include <limits>

#include "cmocka_cpp.hpp"
#include "fsw_app/bar_length_tally.hpp"
#include "fsw_app/handrail_measurement.hpp"
#include "fsw_app/msg_convert.hpp"

namespace {

namespace loc = estimator::localization;

// A vertical bar straight ahead of the camera at range_m: handrail x (the
// wall normal) toward the camera (camera -z), z along the bar (camera -y,
// up in the image), y = z cross x (camera +x).
Eigen::Isometry3d bar_ahead(double range_m) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear().col(0) = Eigen::Vector3d(0, 0, -1);
  T.linear().col(2) = Eigen::Vector3d(0, -1, 0);
  T.linear().col(1) = T.linear().col(2).cross(T.linear().col(0));
  T.translation() = Eigen::Vector3d(0, 0, range_m);
  return T;
}

hrp::handrail_estimate_t estimate(std::int8_t state, const Eigen::Isometry3d& T_cam_handrail) {
  hrp::handrail_estimate_t e{};
  e.capture_utime = 1000;
  e.state = state;
  fsw_app::to_msg(T_cam_handrail, &e.T_cam_handrail);
  return e;
}

void test_length_unknown_until_three_agree(void**) {
  fsw_app::BarLengthTally t;
  assert_true(t.length_m() < 0.0);
  assert_true(t.add_both_ends(0.761));
  assert_true(t.add_both_ends(0.757));
  assert_true(t.length_m() < 0.0);
  assert_true(t.add_both_ends(0.90));  // a stray length: three, but only two agree
  assert_true(t.length_m() < 0.0);
  assert_true(t.add_both_ends(0.764));
  assert_true(std::fabs(t.length_m() - 0.764) < 1e-9);  // the upper median of four
}

void test_implausible_lengths_are_refused(void**) {
  fsw_app::BarLengthTally t;
  assert_false(t.add_both_ends(0.0));  // the message's "not measured"
  assert_false(t.add_both_ends(-0.5));
  assert_false(t.add_both_ends(std::numeric_limits<double>::quiet_NaN()));
  assert_false(t.add_both_ends(std::numeric_limits<double>::infinity()));
  assert_false(t.add_both_ends(3.0));
  assert_true(t.length_m() < 0.0);
}

void test_another_handrail_length_takes_over(void**) {
  fsw_app::BarLengthTally t;
  for (int k = 0; k < 5; ++k) assert_true(t.add_both_ends(0.55));
  assert_true(std::fabs(t.length_m() - 0.55) < 1e-9);
  assert_true(t.add_both_ends(1.04));
  assert_true(t.add_both_ends(1.04));
  assert_true(std::fabs(t.length_m() - 0.55) < 1e-9);  // two of five: still the old bar
  assert_true(t.add_both_ends(1.04));
  assert_true(std::fabs(t.length_m() - 1.04) < 1e-9);
  t.reset();
  assert_true(t.length_m() < 0.0);
}

// The seen end 0.1 m above the image centre, the visible part's middle
// 0.15 m below it (the detector's OE origin): the bar runs downward.
hrp::handrail_estimate_t one_end_seen(const Eigen::Isometry3d& T_bar) {
  Eigen::Isometry3d T_visible = T_bar;
  T_visible.translation() += T_bar.linear().col(2) * -0.05;
  hrp::handrail_estimate_t e = estimate(hrp::handrail_estimate_t::STATE_OE, T_visible);
  const Eigen::Vector3d end = T_bar * Eigen::Vector3d(0, 0, 0.10);
  for (int k = 0; k < 3; ++k) e.ends_cam_m[0][k] = end[k];
  e.num_ends = 1;
  return e;
}

void test_oe_centre_is_half_the_learned_length_from_the_end(void**) {
  const fsw_app::HandrailFeatureModel model;
  const Eigen::Isometry3d T_bar = bar_ahead(0.8);
  const hrp::handrail_estimate_t e = one_end_seen(T_bar);
  loc::HandrailMeasurement m;
  assert_int_equal(static_cast<int>(fsw_app::handrail_measurement_from(e, model, 0.76, &m)),
                   static_cast<int>(fsw_app::HandrailMeasurementStatus::kOk));
  assert_int_equal(static_cast<int>(m.state), static_cast<int>(estimator::HandrailState::kOneEnd));
  const Eigen::Vector3d centre_expected = T_bar * Eigen::Vector3d(0, 0, 0.10 - 0.38);
  assert_true((m.T_cam_handrail.translation() - centre_expected).norm() < 1e-9);
  // A 0.55 m bar from the same view puts the centre 10.5 cm elsewhere: the
  // fault of a configured length on a 0.76 m bar.
  loc::HandrailMeasurement m55;
  (void)fsw_app::handrail_measurement_from(e, model, 0.55, &m55);
  assert_true(std::fabs((m55.T_cam_handrail.translation() - centre_expected).norm() - 0.105) <
              1e-9);
}

void test_oe_without_a_length_is_used_as_ne(void**) {
  const fsw_app::HandrailFeatureModel model;
  const hrp::handrail_estimate_t e = one_end_seen(bar_ahead(0.8));
  loc::HandrailMeasurement m;
  assert_int_equal(static_cast<int>(fsw_app::handrail_measurement_from(e, model, -1.0, &m)),
                   static_cast<int>(fsw_app::HandrailMeasurementStatus::kOk));
  assert_int_equal(static_cast<int>(m.state), static_cast<int>(estimator::HandrailState::kNoEnd));
  // The origin stays the detector's (the visible part's middle).
  assert_true(
      (m.T_cam_handrail.translation() - fsw_app::from_msg(e.T_cam_handrail).translation()).norm() <
      1e-12);
  assert_true(m.num_features > 0);
}

// The wall features' largest and smallest distance from the bar, sideways
// in the handrail frame, and whether all are in the camera's view.
void wall_spread(const loc::HandrailMeasurement& m, const fsw_app::HandrailFeatureModel& model,
                 double* min_m, double* max_m, int* n_wall) {
  *min_m = 1e9;
  *max_m = 0.0;
  *n_wall = 0;
  for (int k = 0; k < m.num_features; ++k) {
    const loc::HandrailFeature& f = m.features[static_cast<std::size_t>(k)];
    if (f.kind != loc::FeatureKind::kWall) continue;
    ++*n_wall;
    const double y = std::fabs(f.p_handrail_m.y());
    *min_m = std::fmin(*min_m, y);
    *max_m = std::fmax(*max_m, y);
    assert_true(std::fabs(f.p_cam_m.x()) <= std::tan(model.half_fov_x_rad) * f.p_cam_m.z());
    assert_true(std::fabs(f.p_cam_m.y()) <= std::tan(model.half_fov_y_rad) * f.p_cam_m.z());
  }
}

void test_wall_features_as_wide_as_the_view(void**) {
  const fsw_app::HandrailFeatureModel model;
  loc::HandrailMeasurement m;
  hrp::handrail_estimate_t e = estimate(hrp::handrail_estimate_t::STATE_BE, bar_ahead(0.9));
  e.bar_length_m = 0.55;
  assert_int_equal(static_cast<int>(fsw_app::handrail_measurement_from(e, model, 0.55, &m)),
                   static_cast<int>(fsw_app::HandrailMeasurementStatus::kOk));
  double lo = 0.0, hi = 0.0;
  int n_wall = 0;
  wall_spread(m, model, &lo, &hi, &n_wall);
  // At 0.9 m the camera sees 0.54 m either side: every wall feature at 20 cm.
  assert_true(n_wall >= 8);
  assert_true(std::fabs(lo - model.wall_half_width_m) < 1e-9);
  assert_true(std::fabs(hi - model.wall_half_width_m) < 1e-9);

  // Close up (the wall 0.25 m from the camera, the bar's centre line 6.1 cm
  // in front of it) the camera sees about 11 cm of wall either side: the
  // features come in, none is lost.
  e = estimate(hrp::handrail_estimate_t::STATE_NE, bar_ahead(0.25 - model.wall_offset_m));
  assert_int_equal(static_cast<int>(fsw_app::handrail_measurement_from(e, model, 0.55, &m)),
                   static_cast<int>(fsw_app::HandrailMeasurementStatus::kOk));
  wall_spread(m, model, &lo, &hi, &n_wall);
  assert_true(n_wall >= 4);
  assert_true(lo >= model.wall_min_half_width_m - 1e-9);
  assert_true(hi < model.wall_half_width_m);
}

}  // namespace

int main() {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_length_unknown_until_three_agree),
      cmocka_unit_test(test_implausible_lengths_are_refused),
      cmocka_unit_test(test_another_handrail_length_takes_over),
      cmocka_unit_test(test_oe_centre_is_half_the_learned_length_from_the_end),
      cmocka_unit_test(test_oe_without_a_length_is_used_as_ne),
      cmocka_unit_test(test_wall_features_as_wide_as_the_view),
  };
  return cmocka_run_group_tests(tests, nullptr, nullptr);
}
