#include <cmath>

#include "arm/arm_model.hpp"
#include "cmocka_cpp.hpp"

namespace {

void test_deployed_arm_points_aft(void**) {
  const arm::ArmGeometry g;
  const Eigen::Isometry3d T =
      arm::forward_kinematics(g, arm::posture_angles(g, arm::Posture::kDeploy));
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
    assert_true(arm::within_limits(g, arm::posture_angles(g, p)));
  }
  assert_false(arm::within_limits(g, {-2.2, 0.0}));  // beyond -120 deg tilt
  assert_false(arm::within_limits(g, {0.0, 1.7}));   // beyond 90 deg pan
  assert_string_equal(arm::to_string(arm::Posture::kStow), "STOW");
}

// The body's x axis seen from the grasp frame, by forward kinematics.
Eigen::Vector3d body_forward_in_grasp(const arm::ArmGeometry& g, const arm::JointAngles& q) {
  const Eigen::Isometry3d T_body_grasp = arm::forward_kinematics(g, q);
  return T_body_grasp.rotation().transpose() * Eigen::Vector3d::UnitX();
}

void test_pointing_inverts_forward_kinematics(void**) {
  const arm::ArmGeometry g;
  int checked = 0;
  for (double tilt = -1.5; tilt <= 1.5; tilt += 0.25) {
    for (double pan = -1.5; pan <= 1.5; pan += 0.25) {
      const arm::JointAngles want{tilt, pan};
      const Eigen::Vector3d d = body_forward_in_grasp(g, want);
      arm::JointAngles got;
      assert_true(arm::pointing_angles(g, 3.0 * d, want, &got));  // any length
      // The same direction, and from the current angles, the same angles.
      assert_true((body_forward_in_grasp(g, got) - d).norm() < 1e-9);
      assert_near(got.tilt_rad, tilt, 1e-9);
      assert_near(got.pan_rad, pan, 1e-9);
      ++checked;
    }
  }
  assert_true(checked > 100);
}

void test_pointing_refuses_unreachable_directions(void**) {
  const arm::ArmGeometry g;
  arm::JointAngles q{0.25, -0.5};
  const arm::JointAngles before = q;
  assert_false(arm::pointing_angles(g, Eigen::Vector3d::Zero(), before, &q));
  // Looking back along the link (body x = grasp +x) needs pan 180 deg.
  assert_false(arm::pointing_angles(g, Eigen::Vector3d::UnitX(), before, &q));
  assert_near(q.tilt_rad, before.tilt_rad, 0.0);  // untouched on failure
  assert_near(q.pan_rad, before.pan_rad, 0.0);
}

void test_grasp_target_puts_the_grasp_point_on_the_bar(void**) {
  const arm::ArmGeometry g;
  // A vertical bar 6 cm off a wall whose normal is world +y, seen with the
  // robot upright (world z up).
  Eigen::Isometry3d T_world_handrail = Eigen::Isometry3d::Identity();
  T_world_handrail.linear().col(0) = Eigen::Vector3d(0, 1, 0);   // normal
  T_world_handrail.linear().col(2) = Eigen::Vector3d(0, 0, -1);  // bar, pointing down
  T_world_handrail.linear().col(1) =
      T_world_handrail.linear().col(2).cross(T_world_handrail.linear().col(0));
  T_world_handrail.translation() = Eigen::Vector3d(1.0, 2.0, 0.5);
  const Eigen::Isometry3d T_world_body =
      arm::grasp_body_target(g, T_world_handrail, Eigen::Vector3d::UnitZ());
  const Eigen::Isometry3d T_world_grasp = T_world_body * arm::forward_kinematics(g, g.grip);
  assert_true((T_world_grasp.translation() - T_world_handrail.translation()).norm() < 1e-12);
  // The link points into the wall, the body stays upright (the bar's sign
  // was flipped to match), and the body is out from the wall by the reach.
  assert_true((T_world_grasp.linear().col(0) - Eigen::Vector3d(0, -1, 0)).norm() < 1e-12);
  assert_true((T_world_body.linear().col(2) - Eigen::Vector3d::UnitZ()).norm() < 1e-12);
  assert_near(T_world_body.translation().y() - 2.0, -g.p_body_base.x() + 0.24, 1e-12);
}

}  // namespace

int main() {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_deployed_arm_points_aft),
      cmocka_unit_test(test_tilt_and_pan_move_the_gripper),
      cmocka_unit_test(test_limits_and_postures),
      cmocka_unit_test(test_pointing_inverts_forward_kinematics),
      cmocka_unit_test(test_pointing_refuses_unreachable_directions),
      cmocka_unit_test(test_grasp_target_puts_the_grasp_point_on_the_bar),
  };
  return cmocka_run_group_tests(tests, nullptr, nullptr);
}
