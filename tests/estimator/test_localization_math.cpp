// The localization filter's parts one by one: rotations, the chi-square
// quantiles, the error-state transition and every measurement Jacobian
// against finite differences of the models themselves, the sequential Joseph
// update against the stacked one, the covariance checks, feature thinning,
// the NE re-anchoring, configuration validation and the status strings.
// The handrail map's parts are in test_localization_map.cpp.
#include <cmath>
#include <cstring>
#include <memory>
#include <random>

#include "cmocka_cpp.hpp"
#include "estimator/localization/config.hpp"
#include "estimator/localization/covariance_check.hpp"
#include "estimator/localization/ekf_update.hpp"
#include "estimator/localization/gates.hpp"
#include "estimator/localization/handrail_map.hpp"
#include "estimator/localization/handrail_update.hpp"
#include "estimator/localization/imu_propagation.hpp"
#include "estimator/localization/pose_update.hpp"
#include "estimator/localization/so3.hpp"
#include "localization_math_helpers.hpp"

using namespace estimator::localization;
using estimator::HandrailState;

namespace {

using namespace locmath;

// ------------------------------------------------------------- rotations

void test_so3(void**) {
  for (const Eigen::Vector3d& phi :
       {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1e-9, -2e-9, 0), Eigen::Vector3d(1e-5, 0, 2e-5),
        Eigen::Vector3d(0.3, -0.2, 0.1), Eigen::Vector3d(0, 3.0, 0)}) {
    const Eigen::Quaterniond q = quat_exp(phi);
    assert_near(q.norm(), 1.0, 1e-15);
    assert_true((quat_log(q) - phi).norm() < 1e-12);
    assert_true((Eigen::AngleAxisd(q).angle() - phi.norm()) < 1e-12);
    assert_true((quat_log(Eigen::Quaterniond(-q.coeffs())) - phi).norm() < 1e-12);
  }
  const Eigen::Vector3d a(1, 2, 3), b(-0.5, 0.25, 4);
  assert_true((skew(a) * b - a.cross(b)).norm() < 1e-15);
}

// ------------------------------------------------------------- gates

void test_chi_square_quantiles(void**) {
  struct Row {
    int dof;
    double p, q;
  };
  // Tabulated values (e.g. NIST/SEMATECH e-Handbook, upper critical values).
  const Row rows[] = {
      {1, 0.999, 10.828},  {2, 0.999, 13.816},  {3, 0.999, 16.266},  {4, 0.999, 18.467},
      {6, 0.999, 22.458},  {10, 0.999, 29.588}, {20, 0.999, 45.315}, {30, 0.999, 59.703},
      {40, 0.999, 73.402}, {60, 0.999, 99.607}, {1, 0.99, 6.635},    {2, 0.99, 9.210},
      {3, 0.99, 11.345},   {6, 0.99, 16.812},   {24, 0.95, 36.415},  {36, 0.95, 50.998}};
  for (const Row& r : rows) assert_near(chi_square_quantile(r.dof, r.p), r.q, 2e-3);
  assert_near(chi_square_cdf(3, 16.266), 0.999, 1e-5);
  const ChiSquareGate gate(0.999);
  assert_near(gate.threshold(6), 22.458, 2e-3);
  assert_true(gate.passes(22.0, 6));
  assert_false(gate.passes(23.0, 6));
  assert_false(gate.passes(-1.0, 6));
  assert_false(gate.passes(std::nan(""), 6));
  assert_false(gate.passes(1.0, 0));  // outside the table nothing passes
  assert_false(gate.passes(1.0, kMaxGateDof + 1));
  assert_true(gate.threshold(kMaxGateDof) > kMaxGateDof);
}

// ------------------------------------------------------------- propagation

void test_transition_matches_finite_differences(void**) {
  LocalizationConfig cfg;
  const NominalState x = some_state();
  ImuSample a, b;
  a.t_us = 1000000;
  b.t_us = a.t_us + 16000;
  a.omega_body_radps = {0.01, -0.02, 0.3};
  b.omega_body_radps = {0.01, -0.02, 0.3};
  a.a_body_mps2 = {0.3, -0.2, 0.1};
  b.a_body_mps2 = {0.3, -0.2, 0.1};
  const auto prop = [&](const NominalState& x0) {
    NominalState y = x0;
    Covariance P = Covariance::Identity();
    propagate_step(cfg, a, b, false, &y, &P);
    return y;
  };
  const NominalState y0 = prop(x);
  // Phi at the mid-step attitude with the bias-corrected specific force.
  const double dt = 0.016;
  const Eigen::Vector3d w = a.omega_body_radps - x.gyro_bias_radps;
  const Eigen::Matrix3d R_mid = (x.q_world_body * quat_exp(0.5 * dt * w)).toRotationMatrix();
  const Covariance Phi = error_transition(R_mid, a.a_body_mps2 - x.accel_bias_mps2, dt);
  for (int i = 0; i < kErrorDim; ++i) {
    const double eps = 1e-6;
    ErrorVector d = ErrorVector::Zero();
    d(i) = eps;
    const ErrorVector num =
        (minus(prop(plus(x, d)), y0) - minus(prop(plus(x, -d)), y0)) / (2 * eps);
    const double err = (num - Phi.col(i)).cwiseAbs().maxCoeff();
    if (err > 2e-6) {
      print_error("Phi column %d differs by %g\n", i, err);
      fail();
    }
  }
}

void test_blockwise_covariance_equals_dense(void**) {
  LocalizationConfig cfg;
  // Noise so small that it does not show: the test is of Phi P Phi^T.
  cfg.imu = {1e-20, 1e-20, 1e-20, 1e-20};
  NominalState x = some_state();
  std::mt19937_64 rng(7);
  std::normal_distribution<double> n(0.0, 1.0);
  Eigen::Matrix<double, kErrorDim, kErrorDim> A;
  for (int i = 0; i < kErrorDim; ++i)
    for (int j = 0; j < kErrorDim; ++j) A(i, j) = n(rng);
  Covariance P = A * A.transpose() + Covariance::Identity();
  const Covariance P0 = P;
  ImuSample a, b;
  a.t_us = 0;
  b.t_us = 16000;
  a.omega_body_radps = b.omega_body_radps = {0.1, 0.2, -0.3};
  a.a_body_mps2 = b.a_body_mps2 = {0.5, 0.1, -0.2};
  const NominalState x0 = x;
  propagate_step(cfg, a, b, false, &x, &P);
  const Eigen::Vector3d w = a.omega_body_radps - x0.gyro_bias_radps;
  const Eigen::Matrix3d R_mid = (x0.q_world_body * quat_exp(0.008 * w)).toRotationMatrix();
  const Covariance Phi = error_transition(R_mid, a.a_body_mps2 - x0.accel_bias_mps2, 0.016);
  const Covariance dense = Phi * P0 * Phi.transpose();
  assert_true((P - dense).cwiseAbs().maxCoeff() < 1e-12 * dense.cwiseAbs().maxCoeff());
}

void test_process_noise_and_gap_rule(void**) {
  LocalizationConfig cfg;
  NominalState x = some_state();
  Covariance P = Covariance::Identity() * 1e-6;
  ImuSample a, b;
  a.t_us = 0;
  b.t_us = 16000;
  assert_int_equal(static_cast<int>(propagate_interval(cfg, a, b, &x, &P)),
                   static_cast<int>(ImuStatus::kPropagated));
  // The velocity variance grows by sigma_a^2 dt (less the tiny Phi terms).
  const double sa = cfg.imu.accel_noise_mps2_rthz;
  assert_near(P(kVel, kVel) - 1e-6, sa * sa * 0.016, 1e-9);
  assert_int_equal(static_cast<int>(classify_interval(cfg, 50000)),
                   static_cast<int>(ImuStatus::kPropagated));
  assert_int_equal(static_cast<int>(classify_interval(cfg, 50001)),
                   static_cast<int>(ImuStatus::kGapBridged));
  assert_int_equal(static_cast<int>(classify_interval(cfg, 1000000)),
                   static_cast<int>(ImuStatus::kGapBridged));
  assert_int_equal(static_cast<int>(classify_interval(cfg, 1000001)),
                   static_cast<int>(ImuStatus::kGapLost));
  // A bridged 0.5 s: 32 sub-steps, with the unmeasured-motion noise; the
  // same interval in one piece or split keeps the rule.
  NominalState x1 = some_state(), x2 = some_state();
  Covariance P1 = Covariance::Identity() * 1e-6, P2 = P1;
  b.t_us = 500000;
  b.omega_body_radps = {0, 0, 0.1};
  assert_int_equal(static_cast<int>(propagate_interval(cfg, a, b, &x1, &P1)),
                   static_cast<int>(ImuStatus::kGapBridged));
  const double su = cfg.gap_accel_sigma_mps2_rthz;
  assert_true(P1(kVel, kVel) > 1e-6 + 0.9 * su * su * 0.5);
  const ImuSample mid = interpolate(a, b, 200000);
  propagate_span(cfg, a, mid, true, &x2, &P2);
  propagate_span(cfg, mid, b, true, &x2, &P2);
  assert_true((x1.p_world_body_m - x2.p_world_body_m).norm() < 1e-9);
  assert_true(std::fabs(P1(kVel, kVel) - P2(kVel, kVel)) < 1e-6 * P1(kVel, kVel));
  // Lost: held, inflated.
  NominalState x3 = some_state();
  Covariance P3 = Covariance::Identity() * 1e-6;
  b.t_us = 2000000;
  assert_int_equal(static_cast<int>(propagate_interval(cfg, a, b, &x3, &P3)),
                   static_cast<int>(ImuStatus::kGapLost));
  assert_true(x3.p_world_body_m == some_state().p_world_body_m);
  assert_near(P3(kPos, kPos), 1e-6 + 0.25, 1e-12);
  assert_true(check_covariance(P3) == Health::kOk);
}

// ------------------------------------------------------------- measurements

void test_gp_jacobian(void**) {
  const NominalState x = some_state();
  GpPose g;
  g.p_world_body_m = x.p_world_body_m + Eigen::Vector3d(0.01, -0.02, 0.005);
  // H's attitude block is I, the log's Jacobian to first order: it is off by
  // about half the residual angle, 1 mrad here.
  g.q_world_body = quat_exp(Eigen::Vector3d(0.001, 0.0, -0.002)) * x.q_world_body;
  const BlockObservation<6> m = gp_observation(g, x);
  // h(x) = z - r(x).
  const auto h = [&](const NominalState& y) {
    const BlockObservation<6> my = gp_observation(g, y);
    Eigen::Matrix<double, 6, 1> z;
    z << g.p_world_body_m, Eigen::Vector3d::Zero();
    return Eigen::Matrix<double, 6, 1>(z - my.r);
  };
  check_jacobian<6>(m.H, h, x, 1.5e-3);
  assert_true(check_gp_pose(g) == UpdateStatus::kAccepted);
}

HandrailFeature some_feature(const NominalState& x, const HandrailMap& map,
                             const Eigen::Vector3d& p_handrail) {
  const LocalizationConfig cfg;
  const FeatureContext c = feature_context(x, cfg.T_body_cam);
  HandrailFeature f;
  f.p_handrail_m = p_handrail;
  f.p_cam_m = c.R_cam_world * (map.T_world_handrail * p_handrail - c.p_world_cam_m) +
              Eigen::Vector3d(0.002, -0.001, 0.003);
  return f;
}

void test_feature_jacobian_eqs_6_to_10(void**) {
  const LocalizationConfig cfg;
  const NominalState x = some_state();
  const HandrailMap map = some_map();
  for (const Eigen::Vector3d& ph :
       {Eigen::Vector3d(0.0175, 0.0, 0.2), Eigen::Vector3d(-0.061, 0.15, -0.1)}) {
    const HandrailFeature f = some_feature(x, map, ph);
    const BlockObservation<3> m = feature_observation(feature_context(x, cfg.T_body_cam), f, 0.004);
    const auto h = [&](const NominalState& y) {
      return Eigen::Vector3d(f.p_cam_m -
                             feature_observation(feature_context(y, cfg.T_body_cam), f, 0.004).r);
    };
    check_jacobian<3>(m.H, h, x, 1e-6);
    assert_true(m.R.isApprox(0.004 * 0.004 * Eigen::Matrix3d::Identity()));
  }
}

void test_feature_jacobian_eqs_11_to_13(void**) {
  const LocalizationConfig cfg;
  const NominalState x = some_state();
  const HandrailMap map = some_map();
  // The detected frame: the predicted one turned by half a degree.
  const FeatureContext c0 = feature_context(x, cfg.T_body_cam);
  const Eigen::Matrix3d R_cam_handrail =
      c0.R_cam_world * map.T_world_handrail.linear() *
      quat_exp(Eigen::Vector3d(0.005, -0.004, 0.003)).toRotationMatrix();
  for (bool reanchor : {false, true}) {
    const HandrailFeature f = some_feature(x, map, Eigen::Vector3d(0.0175, 0.004, 0.12));
    const BlockObservation<2> m =
        feature_observation_no_end(c0, f, R_cam_handrail, 0.004, reanchor);
    // h'(x) = z' - r'(x), with z' the measurement rotated as in eq. 12.
    const Eigen::Vector2d z2 = R_cam_handrail.leftCols<2>().transpose() * f.p_cam_m;
    const auto h = [&](const NominalState& y) {
      return Eigen::Vector2d(z2 - feature_observation_no_end(feature_context(y, cfg.T_body_cam), f,
                                                             R_cam_handrail, 0.004, reanchor)
                                      .r);
    };
    // Re-anchored, the Jacobian is exact to first order in the residual
    // (a few mm here): a looser tolerance.
    check_jacobian<2>(m.H, h, x, reanchor ? 5e-3 : 1e-6);
  }
}

// NE: the detection's along-bar origin is arbitrary. Shift it by 20 cm with
// the detected axis 1 deg off the mapped one: the paper's residual (eq. 12)
// picks up 20 cm x 1 deg = 3.5 mm across the bar; re-anchored, nothing.
void test_no_end_reanchoring_removes_the_along_bar_leak(void**) {
  const LocalizationConfig cfg;
  const NominalState x = some_state();
  const HandrailMap map = some_map();
  const FeatureContext c = feature_context(x, cfg.T_body_cam);
  const Eigen::Matrix3d R_pred = c.R_cam_world * map.T_world_handrail.linear();
  const Eigen::Matrix3d R_det =
      R_pred * quat_exp(Eigen::Vector3d(1.0 * kDeg, 0, 0)).toRotationMatrix();
  HandrailFeature f;
  const Eigen::Vector3d ph(0.0175, 0.0, 0.05);
  f.p_cam_m = c.R_cam_world * (map.T_world_handrail * ph - c.p_world_cam_m);  // exact
  f.p_handrail_m = ph + Eigen::Vector3d(0, 0, 0.20);  // the detection's origin 20 cm off
  const double leak = feature_observation_no_end(c, f, R_det, 0.004, false).r.norm();
  const double reanchored = feature_observation_no_end(c, f, R_det, 0.004, true).r.norm();
  std::printf(
      "  NE residual of an exact feature, origin 20 cm off, axis 1 deg off: %.2f mm as "
      "written, %.2g mm re-anchored\n",
      1e3 * leak, 1e3 * reanchored);
  assert_near(leak, 0.20 * std::sin(1.0 * kDeg), 2e-4);
  assert_true(reanchored < 1e-9);
  // And the re-anchored Jacobian sees nothing along the mapped bar.
  const BlockObservation<2> m = feature_observation_no_end(c, f, R_det, 0.004, true);
  const Eigen::Vector3d axis = map.T_world_handrail.linear().col(2);
  assert_true((m.H.block<2, 3>(0, kPos) * axis).norm() < 1e-12);
  assert_true((m.H.block<2, 3>(0, kMapPos) * axis).norm() < 1e-12);
}

// ------------------------------------------------------------- Joseph

void test_sequential_joseph_equals_stacked(void**) {
  std::mt19937_64 rng(3);
  std::normal_distribution<double> n(0.0, 1.0);
  Eigen::Matrix<double, kErrorDim, kErrorDim> A;
  for (int i = 0; i < kErrorDim; ++i)
    for (int j = 0; j < kErrorDim; ++j) A(i, j) = 0.1 * n(rng);
  const Covariance P0 = A * A.transpose() + 1e-3 * Covariance::Identity();
  BlockObservation<3> b1, b2;
  BlockObservation<6> stacked;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < kErrorDim; ++j) {
      b1.H(i, j) = n(rng);
      b2.H(i, j) = n(rng);
    }
    b1.r(i) = 0.1 * n(rng);
    b2.r(i) = 0.1 * n(rng);
  }
  b1.R = 0.01 * Eigen::Matrix3d::Identity();
  b2.R = 0.02 * Eigen::Matrix3d::Identity();
  stacked.H << b1.H, b2.H;
  stacked.r << b1.r, b2.r;
  stacked.R.setZero();
  stacked.R.topLeftCorner<3, 3>() = b1.R;
  stacked.R.bottomRightCorner<3, 3>() = b2.R;

  Covariance Ps = P0, Pb = P0;
  ErrorVector dxs = ErrorVector::Zero(), dxb = ErrorVector::Zero();
  double n1 = 0, n2 = 0, nb = 0;
  assert_true(joseph_update(b1, &Ps, &dxs, &n1));
  assert_true(joseph_update(b2, &Ps, &dxs, &n2));
  assert_true(joseph_update(stacked, &Pb, &dxb, &nb));
  assert_true((Ps - Pb).cwiseAbs().maxCoeff() < 1e-12);
  assert_true((dxs - dxb).cwiseAbs().maxCoeff() < 1e-12);
  assert_near(n1 + n2, nb, 1e-9 * nb);
  // Joseph against the textbook P - K S K^T at the optimal gain.
  const Eigen::Matrix<double, 6, 6> S = stacked.H * P0 * stacked.H.transpose() + stacked.R;
  const Eigen::Matrix<double, kErrorDim, 6> K = P0 * stacked.H.transpose() * S.inverse();
  const Covariance short_form = P0 - K * S * K.transpose();
  assert_true((Pb - short_form).cwiseAbs().maxCoeff() < 1e-12);
  assert_true(check_covariance(Pb) == Health::kOk);
  // The prior NIS of a block alone.
  double nis = 0;
  assert_true(block_nis(b1, P0, &nis));
  assert_near(nis, n1, 1e-12);
  // S not positive definite: refused, untouched.
  BlockObservation<3> bad = b1;
  bad.R = -10.0 * Eigen::Matrix3d::Identity();
  bad.H.setZero();
  Covariance Pc = P0;
  ErrorVector dxc = ErrorVector::Zero();
  assert_false(joseph_update(bad, &Pc, &dxc, &nis));
  assert_true(Pc == P0);
}

void test_covariance_checks(void**) {
  Covariance P = Covariance::Identity();
  assert_true(check_covariance(P) == Health::kOk);
  P(3, 4) = 1e-3;
  assert_true(check_covariance(P) == Health::kNotSymmetric);
  P(4, 3) = 1e-3;
  assert_true(check_covariance(P) == Health::kOk);
  P(2, 2) = 0.0;
  assert_true(check_covariance(P) == Health::kNotPositiveDefinite);
  P(2, 2) = 1.0;
  P(0, 1) = P(1, 0) = 2.0;  // positive diagonal, indefinite
  assert_true(check_covariance(P) == Health::kNotPositiveDefinite);
  P(0, 1) = P(1, 0) = std::nan("");
  assert_true(check_covariance(P) == Health::kNotFinite);
  NominalState x;
  x.q_world_body.coeffs() *= 1.001;
  assert_true(check_filter(x, Covariance::Identity()) == Health::kQuaternionNotUnit);
  x = NominalState{};
  x.v_world_body_mps.y() = std::nan("");
  assert_true(check_filter(x, Covariance::Identity()) == Health::kStateNotFinite);
}

// ------------------------------------------------------------- features, map

void test_feature_thinning(void**) {
  auto m = std::make_unique<HandrailMeasurement>();
  m->state = HandrailState::kBothEnds;
  Eigen::Vector3d bar[40], wall[20];
  for (int i = 0; i < 40; ++i) bar[i] = {0.0, 0.0, 0.6 + 0.01 * i};  // camera frame = handrail here
  for (int i = 0; i < 20; ++i) wall[i] = {0.1 * (i % 5), -0.2 + 0.1 * (i / 5), 0.5};
  assert_int_equal(add_features(bar, 40, FeatureKind::kBar, m.get()), 40);
  assert_int_equal(add_features(wall, 20, FeatureKind::kWall, m.get()), 20);
  assert_int_equal(add_features(wall, 20, FeatureKind::kWall, m.get()), 4);  // full at 64
  m->num_features = 60;
  SelectedFeatures s;
  select_features(*m, 8, 4, &s);
  assert_int_equal(s.num_features, 12);
  double zmin = 1e9, zmax = -1e9;
  int bars = 0;
  for (int k = 0; k < s.num_features; ++k) {
    const HandrailFeature& f = s.features[static_cast<std::size_t>(k)];
    if (f.kind != FeatureKind::kBar) continue;
    ++bars;
    zmin = std::min(zmin, f.p_handrail_m.z());
    zmax = std::max(zmax, f.p_handrail_m.z());
  }
  assert_int_equal(bars, 8);
  // Spread: both extremes of the bar are among the eight.
  assert_near(zmin, 0.6, 1e-12);
  assert_near(zmax, 0.99, 1e-12);
  // Deterministic, and bounded by the fixed maxima.
  SelectedFeatures s2;
  select_features(*m, 8, 4, &s2);
  for (int k = 0; k < s.num_features; ++k) {
    assert_true(s.features[static_cast<std::size_t>(k)].p_cam_m ==
                s2.features[static_cast<std::size_t>(k)].p_cam_m);
  }
  select_features(*m, 100, 100, &s2);
  assert_int_equal(s2.num_features, kMaxUsedBarFeatures + kMaxUsedWallFeatures);
}

void test_axis_alignment_with_the_map(void**) {
  const LocalizationConfig cfg;
  const NominalState x = some_state();
  const HandrailMap map = some_map();
  const FeatureContext c = feature_context(x, cfg.T_body_cam);
  SelectedFeatures s;
  s.state = HandrailState::kBothEnds;
  s.R_cam_handrail = flip_axis(c.R_cam_world * map.T_world_handrail.linear());
  s.num_features = 1;
  s.features[0].p_handrail_m = {0.01, 0.02, 0.2};
  align_with_map(x, cfg.T_body_cam, &s);
  assert_true(s.R_cam_handrail.isApprox(c.R_cam_world * map.T_world_handrail.linear(), 1e-12));
  assert_true(s.features[0].p_handrail_m.isApprox(Eigen::Vector3d(0.01, -0.02, -0.2)));
  align_with_map(x, cfg.T_body_cam, &s);  // aligned: unchanged
  assert_true(s.features[0].p_handrail_m.isApprox(Eigen::Vector3d(0.01, -0.02, -0.2)));
}

// ------------------------------------------------------------- the rest

void test_configuration(void**) {
  LocalizationConfig c;
  assert_null(validate(c));
  c.max_bar_features = kMaxUsedBarFeatures + 1;
  assert_string_equal(validate(c), "max_bar_features");
  c = LocalizationConfig{};
  c.max_imu_gap_s = 5.0;  // 312 sub-steps at 62.5 Hz: beyond kMaxGapSubsteps
  assert_string_equal(validate(c), "max_imu_gap_s");
  c = LocalizationConfig{};
  c.T_body_cam.linear() *= 2.0;
  assert_string_equal(validate(c), "T_body_cam");
  c = LocalizationConfig{};
  c.gate_probability = 1.0;
  assert_string_equal(validate(c), "gate_probability");
  c = LocalizationConfig{};
  c.min_features = 13;
  assert_string_equal(validate(c), "min_features");
}

void test_status_strings(void**) {
  for (int s = 0; s < kNumImuStatus; ++s) {
    assert_string_not_equal(to_string(static_cast<ImuStatus>(s)), "UNKNOWN");
  }
  for (int s = 0; s < kNumUpdateStatus; ++s) {
    assert_string_not_equal(to_string(static_cast<UpdateStatus>(s)), "UNKNOWN");
  }
  for (int s = 0; s < kNumMeasurementKinds; ++s) {
    assert_string_not_equal(to_string(static_cast<MeasurementKind>(s)), "UNKNOWN");
  }
  for (int s = 0; s <= static_cast<int>(Health::kNotPositiveDefinite); ++s) {
    assert_string_not_equal(to_string(static_cast<Health>(s)), "UNKNOWN");
  }
  assert_string_equal(to_string(static_cast<UpdateStatus>(kNumUpdateStatus)), "UNKNOWN");
  assert_string_equal(to_string(UpdateStatus::kRejectedGate), "REJECTED_GATE");
  assert_true(is_rejection(UpdateStatus::kRejectedGate));
  assert_false(is_rejection(UpdateStatus::kNoMap));
  assert_false(is_rejection(UpdateStatus::kMapSighting));
}

}  // namespace

int main() {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_so3),
      cmocka_unit_test(test_chi_square_quantiles),
      cmocka_unit_test(test_transition_matches_finite_differences),
      cmocka_unit_test(test_blockwise_covariance_equals_dense),
      cmocka_unit_test(test_process_noise_and_gap_rule),
      cmocka_unit_test(test_gp_jacobian),
      cmocka_unit_test(test_feature_jacobian_eqs_6_to_10),
      cmocka_unit_test(test_feature_jacobian_eqs_11_to_13),
      cmocka_unit_test(test_no_end_reanchoring_removes_the_along_bar_leak),
      cmocka_unit_test(test_sequential_joseph_equals_stacked),
      cmocka_unit_test(test_covariance_checks),
      cmocka_unit_test(test_feature_thinning),
      cmocka_unit_test(test_axis_alignment_with_the_map),
      cmocka_unit_test(test_configuration),
      cmocka_unit_test(test_status_strings),
  };
  return cmocka_run_group_tests(tests, nullptr, nullptr);
}
