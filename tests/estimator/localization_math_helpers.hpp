// Shared by the localization parts' tests (test_localization_math.cpp,
// test_localization_map.cpp): the filter's own injection and its inverse,
// a state and a map to test at, and a Jacobian checked against finite
// differences over the whole error state.
#pragma once

#include "cmocka_cpp.hpp"
#include "estimator/localization/handrail_map.hpp"
#include "estimator/localization/so3.hpp"
#include "estimator/localization/state.hpp"

namespace locmath {

using namespace estimator::localization;

constexpr double kDeg = 3.14159265358979323846 / 180.0;

// x (+) dx, the filter's own injection without the covariance.
inline NominalState plus(const NominalState& x, const ErrorVector& dx) {
  NominalState y = x;
  Covariance P = Covariance::Identity();
  inject(dx, &y, &P);
  return y;
}

// The error between two states, inverse of plus() (attitude to first order
// of the log, exact).
inline ErrorVector minus(const NominalState& a, const NominalState& b) {
  ErrorVector d;
  d.segment<3>(kPos) = a.p_world_body_m - b.p_world_body_m;
  d.segment<3>(kVel) = a.v_world_body_mps - b.v_world_body_mps;
  d.segment<3>(kAtt) = quat_log(a.q_world_body * b.q_world_body.conjugate());
  d.segment<3>(kGyroBias) = a.gyro_bias_radps - b.gyro_bias_radps;
  d.segment<3>(kAccelBias) = a.accel_bias_mps2 - b.accel_bias_mps2;
  d.segment<3>(kMapPos) = a.p_world_handrail_m - b.p_world_handrail_m;
  d.segment<3>(kMapAtt) = quat_log(a.q_world_handrail * b.q_world_handrail.conjugate());
  return d;
}

inline HandrailMap some_map() {
  HandrailMap m;
  m.valid = true;
  m.T_world_handrail.linear() = quat_exp(Eigen::Vector3d(0.01, 0.02, -0.03)).toRotationMatrix();
  m.T_world_handrail.translation() = Eigen::Vector3d(0.061, 0.01, 0.0);
  return m;
}

inline NominalState some_state() {
  NominalState x;
  x.p_world_body_m = {0.9, 0.05, -0.06};
  x.v_world_body_mps = {0.02, -0.03, 0.01};
  x.q_world_body = quat_exp(Eigen::Vector3d(0.05, -0.03, 0.2));
  x.gyro_bias_radps = {0.002, -0.001, 0.0015};
  x.accel_bias_mps2 = {0.01, -0.02, 0.005};
  // The map in the state is some_map()'s.
  const HandrailMap m = some_map();
  x.p_world_handrail_m = m.T_world_handrail.translation();
  x.q_world_handrail = Eigen::Quaterniond(m.T_world_handrail.linear());
  return x;
}

template <int D, class Model>
void check_jacobian(const Eigen::Matrix<double, D, kErrorDim>& H, Model&& h, const NominalState& x,
                    double tol) {
  // h(x) is the prediction; r = z - h, so dh/ddx = H.
  for (int i = 0; i < kErrorDim; ++i) {
    const double eps = 1e-6;
    ErrorVector d = ErrorVector::Zero();
    d(i) = eps;
    const Eigen::Matrix<double, D, 1> num = (h(plus(x, d)) - h(plus(x, -d))) / (2 * eps);
    const double err = (num - H.col(i)).cwiseAbs().maxCoeff();
    if (err > tol) {
      print_error("column %d: numeric vs analytic differ by %g\n", i, err);
      fail();
    }
  }
}

}  // namespace locmath
