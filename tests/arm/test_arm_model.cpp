#include <cmath>

#include "arm/arm_model.hpp"
#include "cmocka_cpp.hpp"

namespace {

void test_deployed_arm_points_aft(void**) {
  const arm::ArmGeometry g;
  const Eigen::Isometry3d T =
      arm::forward_kinematics(g, arm::posture_angles(arm::Posture::kDeploy));
  const double reach = g.proximal_link_m + g.distal_link_m;
  assert_near(T.translation().x(), g.p_body_base.x() - reach, 1e-9);
  assert_near(T.translation().y(), g.p_body_base.y(), 1e-9);
  assert_near(T.translation().z(), g.p_body_base.z(), 1e-9);
  assert_near(T.rotation().col(0).x(), -1.0, 1e-9);  // link outward = aft
}

void test_tilt_and_pan_move_the_gripper(void**) {
  const arm::ArmGeometry g;
  // Tilting 90 deg folds the whole arm to point straight down or up; the
  // gripper stays at link length from the joint.
  const Eigen::Isometry3d T = arm::forward_kinematics(g, {M_PI / 2, 0.0});
  assert_near((T.translation() - g.p_body_base).norm(), g.proximal_link_m + g.distal_link_m, 1e-9);
  assert_near(std::fabs(T.translation().z() - g.p_body_base.z()),
              g.proximal_link_m + g.distal_link_m, 1e-9);
  // Panning moves only the distal link.
  const Eigen::Isometry3d P = arm::forward_kinematics(g, {0.0, M_PI / 2});
  const Eigen::Vector3d elbow = g.p_body_base - Eigen::Vector3d(g.proximal_link_m, 0, 0);
  assert_near((P.translation() - elbow).norm(), g.distal_link_m, 1e-9);
  assert_near(std::fabs(P.translation().y()), g.distal_link_m, 1e-9);
}

void test_limits_and_postures(void**) {
  const arm::ArmGeometry g;
  for (arm::Posture p : {arm::Posture::kStow, arm::Posture::kDeploy, arm::Posture::kGrip}) {
    assert_true(arm::within_limits(g, arm::posture_angles(p)));
  }
  assert_false(arm::within_limits(g, {-2.2, 0.0}));  // beyond -120 deg tilt
  assert_false(arm::within_limits(g, {0.0, 1.7}));   // beyond 90 deg pan
  assert_string_equal(arm::to_string(arm::Posture::kStow), "STOW");
}

}  // namespace

int main() {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_deployed_arm_points_aft),
      cmocka_unit_test(test_tilt_and_pan_move_the_gripper),
      cmocka_unit_test(test_limits_and_postures),
  };
  return cmocka_run_group_tests(tests, nullptr, nullptr);
}
