// The handrail map's parts: a sighted map's correlation with the robot and
// a survey's block (map_state.hpp), the body's position in the handrail
// frame and its covariance, both against finite differences, and the map
// builder (sightings with ends, and the line map from sightings without).
#include <cmath>

#include "cmocka_cpp.hpp"
#include "estimator/localization/config.hpp"
#include "estimator/localization/covariance_check.hpp"
#include "estimator/localization/handrail_map.hpp"
#include "estimator/localization/map_state.hpp"
#include "localization_math_helpers.hpp"

using namespace estimator::localization;

namespace {

using namespace locmath;

// A map placed from the robot's pose carries the robot's error: the map
// block's cross-covariance J P must be the true first-order dependence of
// the sighted map on the robot's pose (checked by finite differences of
// T_world_body T_body_handrail), and the map's own covariance J P J^T plus
// the sighting's noise.
void test_sighted_map_inherits_the_robot_error(void**) {
  LocalizationConfig cfg;
  NominalState x = some_state();
  Eigen::Isometry3d T_world_body = Eigen::Isometry3d::Identity();
  T_world_body.linear() = x.q_world_body.toRotationMatrix();
  T_world_body.translation() = x.p_world_body_m;
  const Eigen::Isometry3d T_body_handrail = T_world_body.inverse() * some_map().T_world_handrail;
  // A covariance with robot entries only: diagonal, so that P's columns
  // pick out J's.
  Covariance P = 1e-4 * Covariance::Identity();
  attach_sighted_map(cfg, T_world_body * T_body_handrail, &x, &P);
  assert_true(check_covariance(P) == Health::kOk);
  const auto sighted = [&](const NominalState& y) {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = y.q_world_body.toRotationMatrix();
    T.translation() = y.p_world_body_m;
    NominalState m = y;
    const Eigen::Isometry3d T_map = T * T_body_handrail;
    m.p_world_handrail_m = T_map.translation();
    m.q_world_handrail = Eigen::Quaterniond(T_map.linear());
    return m;
  };
  for (int i = 0; i < kMapPos; ++i) {
    const double eps = 1e-6;
    ErrorVector d = ErrorVector::Zero();
    d(i) = eps;
    const ErrorVector num =
        (minus(sighted(plus(x, d)), x) - minus(sighted(plus(x, -d)), x)) / (2 * eps);
    // P(map, i) / P(i, i) is J's column i.
    const Eigen::Matrix<double, 6, 1> J_col = P.block<6, 1>(kMapPos, i) / 1e-4;
    if ((num.segment<6>(kMapPos) - J_col).cwiseAbs().maxCoeff() > 1e-6) {
      print_error("map column %d: numeric vs attached differ\n", i);
      fail();
    }
  }
  // Position: the robot's 1 cm plus the attitude's 1 cm per metre of lever
  // plus the sighting's 1 cm.
  const double lever2 = (x.p_world_handrail_m - x.p_world_body_m).squaredNorm();
  const double sigma2 = cfg.map_sighting_position_sigma_m * cfg.map_sighting_position_sigma_m;
  const double map_var = P.block<3, 3>(kMapPos, kMapPos).trace();
  assert_true(map_var > 3e-4 + 3 * sigma2);
  assert_near(map_var, 3e-4 + 2e-4 * lever2 + 3 * sigma2, 1e-9);
  // A survey: its own sigmas, uncorrelated.
  HandrailMap survey = some_map();
  survey.surveyed = true;
  survey.position_sigma_m = 0.002;
  survey.attitude_sigma_rad = 0.001;
  attach_surveyed_map(survey, &x, &P);
  const bool uncorrelated = P.block<6, kMapPos>(kMapPos, 0).isZero();
  assert_true(uncorrelated);
  assert_near(P(kMapPos, kMapPos), 0.002 * 0.002 + 1e-8, 1e-15);
  assert_near(P(kMapAtt, kMapAtt), 0.001 * 0.001 + 1e-10, 1e-15);
  assert_true(check_covariance(P) == Health::kOk);
}

// The body in the handrail's frame and its covariance: a robot whose error
// is the map's (fully correlated, as right after a sighting with no
// detection noise) is exactly known relative to the bar.
void test_body_in_handrail(void**) {
  NominalState x = some_state();
  const Eigen::Vector3d p_h = body_in_handrail(x);
  const HandrailMap map = some_map();
  assert_true((p_h - map.T_world_handrail.inverse() * x.p_world_body_m).norm() < 1e-12);
  // Its Jacobian by finite differences, through the covariance of unit
  // variances one state at a time.
  for (int i = 0; i < kErrorDim; ++i) {
    const double eps = 1e-6;
    ErrorVector d = ErrorVector::Zero();
    d(i) = eps;
    const Eigen::Vector3d num =
        (body_in_handrail(plus(x, d)) - body_in_handrail(plus(x, -d))) / (2 * eps);
    Covariance P = Covariance::Zero();
    P(i, i) = 1.0;
    const Eigen::Matrix3d C = body_in_handrail_cov(x, P);
    if ((C - num * num.transpose()).cwiseAbs().maxCoeff() > 1e-8) {
      print_error("state %d: body-in-handrail covariance differs\n", i);
      fail();
    }
  }
  LocalizationConfig cfg;
  cfg.map_sighting_position_sigma_m = 1e-9;
  cfg.map_sighting_attitude_sigma_rad = 1e-9;
  Covariance P = 1e-4 * Covariance::Identity();
  attach_sighted_map(cfg, map.T_world_handrail, &x, &P);
  assert_true(body_in_handrail_cov(x, P).trace() < 1e-12);
}

void test_handrail_map_builder(void**) {
  LocalizationConfig cfg;
  HandrailMapBuilder b;
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation() = Eigen::Vector3d(0.061, 0.0, 0.0);
  bool restarted = false;
  Eigen::Isometry3d T1 = T;
  T1.translation().y() += 0.004;
  assert_true(b.add_sighting(cfg, T1, true, &restarted) == UpdateStatus::kMapSighting);
  // The same bar with its axis reversed counts as the same sighting.
  Eigen::Isometry3d T2 = T;
  T2.linear() = flip_axis(T.linear());
  T2.translation().y() -= 0.004;
  assert_true(b.add_sighting(cfg, T2, true, &restarted) == UpdateStatus::kMapSighting);
  assert_false(restarted);
  // One far off restarts the count from itself.
  Eigen::Isometry3d T3 = T;
  T3.translation().z() += 0.1;
  assert_true(b.add_sighting(cfg, T3, true, &restarted) == UpdateStatus::kMapSighting);
  assert_true(restarted);
  assert_int_equal(b.sightings(), 1);
  assert_true(b.add_sighting(cfg, T3, true, &restarted) == UpdateStatus::kMapSighting);
  const Eigen::Isometry3d T4 = T3 * Eigen::AngleAxisd(0.01, Eigen::Vector3d::UnitY());
  assert_true(b.add_sighting(cfg, T4, true, &restarted) == UpdateStatus::kMapInitialized);
  assert_true(b.map().valid);
  assert_true((b.map().T_world_handrail.translation() - T3.translation()).norm() < 1e-12);
  const double angle = Eigen::AngleAxisd(b.map().T_world_handrail.linear()).angle();
  assert_near(angle, 0.01 / 3.0, 1e-6);
  assert_true(b.map().along_known);

  // No end seen: a line map. Origins 20 and 35 cm along the bar agree (they
  // only slide along it); the map keeps the first one's. One 4 cm across
  // restarts the count. During a count with ends, a sighting without one
  // is refused; an end seen during a line count restarts it with ends.
  HandrailMapBuilder line;
  Eigen::Isometry3d L1 = T;
  L1.translation().z() += 0.20;
  Eigen::Isometry3d L2 = T;
  L2.translation().z() += 0.35;
  L2.translation().y() += 0.003;
  Eigen::Isometry3d L3 = T;
  L3.translation().y() += 0.04;
  assert_true(line.add_sighting(cfg, L1, false, &restarted) == UpdateStatus::kMapSighting);
  assert_true(line.add_sighting(cfg, L2, false, &restarted) == UpdateStatus::kMapSighting);
  assert_false(restarted);
  assert_true(line.add_sighting(cfg, L3, false, &restarted) == UpdateStatus::kMapSighting);
  assert_true(restarted);
  Eigen::Isometry3d L4 = L3;
  L4.translation().z() += 0.10;
  Eigen::Isometry3d L5 = L3;
  L5.translation().z() -= 0.05;
  L5.translation().y() += 0.003;
  assert_true(line.add_sighting(cfg, L4, false, &restarted) == UpdateStatus::kMapSighting);
  assert_true(line.add_sighting(cfg, L5, false, &restarted) == UpdateStatus::kMapInitialized);
  assert_true(line.map().valid);
  assert_false(line.map().along_known);
  // L3 started the count: the origin is L3's along the bar, the mean across.
  const Eigen::Vector3d origin = line.map().T_world_handrail.translation();
  assert_near(origin.z(), L3.translation().z(), 1e-12);
  assert_near(origin.y(), L3.translation().y() + 0.001, 1e-12);
  HandrailMapBuilder ends;
  assert_true(ends.add_sighting(cfg, T, true, &restarted) == UpdateStatus::kMapSighting);
  assert_true(ends.add_sighting(cfg, L1, false, &restarted) == UpdateStatus::kNoMap);
  assert_int_equal(ends.sightings(), 1);
  HandrailMapBuilder upgraded;
  assert_true(upgraded.add_sighting(cfg, L1, false, &restarted) == UpdateStatus::kMapSighting);
  assert_true(upgraded.add_sighting(cfg, T, true, &restarted) == UpdateStatus::kMapSighting);
  assert_int_equal(upgraded.sightings(), 1);
}

}  // namespace

int main() {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_sighted_map_inherits_the_robot_error),
      cmocka_unit_test(test_body_in_handrail),
      cmocka_unit_test(test_handrail_map_builder),
  };
  return cmocka_run_group_tests(tests, nullptr, nullptr);
}
