// The approach controller against the simulated free-flyer, in lock step
// on simulated time: from a metre out it reaches the grasp pose within
// tolerance and settles ("at target"), through the flyer's disturbances;
// it holds while the arm is not ready, and backs off after letting go;
// it holds while frames are late and flies on when they come back.
#include <cmath>
#include <cstdio>

#include "cmocka_cpp.hpp"
#include "fsw_app/msg_convert.hpp"
#include "fsw_app/perch_manager.hpp"
#include "sim_hal/flyer.hpp"

namespace {

using A = hrp::arm_state_t;

struct Loop {
  fsw_app::ApproachConfig cfg;
  Eigen::Vector3d p_body_grasp = arm::forward_kinematics(arm::ArmGeometry{}, {}).translation();
  fsw_app::ApproachController ctl{cfg, p_body_grasp};
  Eigen::Isometry3d T_world_handrail = Eigen::Isometry3d::Identity();
  Eigen::Isometry3d T_world_target = Eigen::Isometry3d::Identity();
  sim_hal::SimFlyer flyer;
  std::int64_t now_us = 0;
  fsw_app::ApproachOutput out;
  // The pose the manager is handed: this old, marked lost, from this source.
  std::int64_t pose_age_us = 0;
  bool pose_lost = false;
  std::int8_t pose_source = hrp::robot_pose_t::SOURCE_FILTER;
  // Its 1-sigma per axis, as the filter claims it: a GP-fed filter's.
  double pose_position_sigma_m = 0.02;
  double pose_attitude_sigma_rad = 0.01;
  // The camera: while on, an estimate per frame period (5 fps), captured
  // 50 ms before the manager gets it.
  bool camera_on = true;
  hrp::handrail_estimate_t estimate{};

  explicit Loop(std::uint64_t seed) : flyer(start_pose(), sim_hal::FlyerParams{}, seed) {
    // The wall normal is world +x; the bar runs along world z.
    T_world_handrail.linear().col(0) = Eigen::Vector3d::UnitX();
    T_world_handrail.linear().col(1) = Eigen::Vector3d::UnitY();
    T_world_handrail.linear().col(2) = Eigen::Vector3d::UnitZ();
    T_world_handrail.translation() = Eigen::Vector3d(0.06, 0.0, 0.0);
    T_world_target = T_world_handrail;
    T_world_target.linear() = Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    T_world_target.translation() = Eigen::Vector3d(0.46, 0.0, 0.05);
    hrp::handrail_estimate_t& e = estimate;
    e.state = hrp::handrail_estimate_t::STATE_NE;
    e.capture_utime = 1;
    e.target_in_world = true;
    fsw_app::to_msg(T_world_target, &e.T_world_target);
    fsw_app::to_msg(T_world_handrail, &e.T_world_handrail);
    ctl.on_estimate(e);
  }
  static Eigen::Isometry3d start_pose() {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = (Eigen::AngleAxisd(M_PI + 0.1, Eigen::Vector3d::UnitZ()) *
                  Eigen::AngleAxisd(0.05, Eigen::Vector3d::UnitY()))
                     .toRotationMatrix();
    T.translation() = Eigen::Vector3d(1.4, 0.08, 0.0);
    return T;
  }
  // Runs the controller at 20 Hz and the flyer at 100 Hz for `seconds`.
  void run(double seconds, std::int8_t arm_state) {
    for (int k = 0; k < seconds * 100; ++k) {
      now_us += 10000;
      if (camera_on && now_us % cfg.frame_period_us == 0) {
        estimate.capture_utime = now_us - 50000;
        ctl.on_estimate(estimate);
      }
      if (k % 5 == 0) {
        hrp::robot_pose_t pose{};
        pose.utime = now_us - pose_age_us;
        pose.source = pose_source;
        pose.lost = pose_lost;
        for (int i = 0; i < 3; ++i) {
          pose.pose_covariance[i][i] = pose_position_sigma_m * pose_position_sigma_m;
          pose.pose_covariance[3 + i][3 + i] = pose_attitude_sigma_rad * pose_attitude_sigma_rad;
        }
        fsw_app::to_msg(flyer.pose(), &pose.T_world_body);
        for (int i = 0; i < 3; ++i) pose.velocity_mps[i] = flyer.velocity()[i];
        out = ctl.step(now_us, &pose, arm_state);
      }
      Eigen::Vector3d v = Eigen::Vector3d::Zero(), w = Eigen::Vector3d::Zero();
      if (!out.velocity.hold) {
        v = Eigen::Vector3d(out.velocity.velocity_mps[0], out.velocity.velocity_mps[1],
                            out.velocity.velocity_mps[2]);
        w = Eigen::Vector3d(out.velocity.angular_velocity_rps[0],
                            out.velocity.angular_velocity_rps[1],
                            out.velocity.angular_velocity_rps[2]);
      }
      flyer.step(0.01, v, w);
    }
  }
  std::int64_t ctl_frame_seen() const { return estimate.capture_utime; }
  // The grasp point's error.
  double error_m() const {
    return (flyer.pose() * p_body_grasp - T_world_target * p_body_grasp).norm();
  }
};

void test_reaches_and_settles_on_the_grasp_pose(void**) {
  for (std::uint64_t seed = 1; seed <= 10; ++seed) {
    Loop loop(seed);
    loop.run(2.0, A::STOWED);  // not perching: holds
    assert_true(loop.out.velocity.hold);
    loop.run(12.0, A::DEPLOYING);  // to the stand-off pose
    const double standoff_err =
        (loop.flyer.pose().translation() -
         (loop.T_world_target.translation() + loop.cfg.standoff_m * Eigen::Vector3d::UnitX()))
            .norm();
    double t_at = -1.0;
    for (int k = 0; k < 400 && t_at < 0.0; ++k) {
      loop.run(0.1, A::GRIPPER_OPEN);
      if (loop.out.status.at_target) t_at = 0.1 * (k + 1);
    }
    const double at_err = loop.error_m();
    loop.run(1.5, A::CLOSING);  // station keeping while the fingers close
    std::printf(
        "seed %llu: stand-off error %.1f mm, at target after %.1f s, error %.1f mm, after the "
        "close %.1f mm\n",
        static_cast<unsigned long long>(seed), standoff_err * 1000.0, t_at, at_err * 1000.0,
        loop.error_m() * 1000.0);
    assert_true(standoff_err < 0.02);
    assert_true(t_at > 0.0);
    assert_true(at_err <= loop.cfg.position_tolerance_m + 0.001);
    assert_true(loop.error_m() <= loop.cfg.position_tolerance_m);
  }
}

void test_backs_off_after_letting_go(void**) {
  Loop loop(3);
  loop.flyer.hold_at(loop.T_world_target);
  loop.run(0.5, A::UNPERCHING);
  assert_true(loop.out.velocity.hold);
  loop.run(10.0, A::BACKING_OFF);
  assert_true(loop.out.status.backed_off);
  const double out_m = loop.flyer.pose().translation().x() - loop.T_world_target.translation().x();
  assert_true(out_m > 0.9 * loop.cfg.back_off_m);
}

// Without a pose it can fly on (older than pose_max_age_ms, marked lost,
// from anything but the filter, or spread wider than the filter's own
// bounds allow), the manager holds the robot still and
// says since when; with one again it flies on.
void test_holds_without_a_fresh_filter_pose(void**) {
  Loop loop(4);
  loop.run(3.0, A::DEPLOYING);
  assert_false(loop.out.velocity.hold);
  assert_true(loop.out.status.pose_usable);
  assert_int_equal(loop.out.status.pose_unusable_since_utime, -1);
  const auto holds = [&loop](const char* why) {
    loop.run(0.5, A::DEPLOYING);
    std::printf("  %s: hold %d, usable %d\n", why, loop.out.velocity.hold,
                loop.out.status.pose_usable);
    assert_true(loop.out.velocity.hold);
    assert_false(loop.out.status.pose_usable);
    assert_true(loop.out.status.pose_unusable_since_utime > 0);
  };
  loop.pose_age_us = 1000LL * loop.cfg.pose_max_age_ms + 50000;
  holds("pose 300 ms old");
  const std::int64_t since = loop.out.status.pose_unusable_since_utime;
  loop.pose_age_us = 0;
  loop.pose_lost = true;
  holds("pose marked lost");
  assert_int_equal(loop.out.status.pose_unusable_since_utime, since);  // one outage
  loop.pose_lost = false;
  loop.pose_source = hrp::robot_pose_t::SOURCE_GP;
  holds("pose from the GP");
  loop.pose_source = hrp::robot_pose_t::SOURCE_TRUTH;
  holds("pose from the truth");
  loop.pose_source = hrp::robot_pose_t::SOURCE_FILTER;
  // 0.9 m per axis is 1.56 m radial: past the 1.5 m bound. 0.6 m per
  // axis (a GP off by a metre) flies.
  loop.pose_position_sigma_m = 0.9;
  holds("position 1.56 m uncertain");
  loop.pose_position_sigma_m = 0.6;
  loop.pose_attitude_sigma_rad = 0.31;  // 0.54 rad radial, 31 deg
  holds("attitude 31 deg uncertain");
  loop.pose_attitude_sigma_rad = 0.1;
  loop.run(0.5, A::DEPLOYING);
  assert_false(loop.out.velocity.hold);
  assert_true(loop.out.status.pose_usable);
  assert_int_equal(loop.out.status.pose_unusable_since_utime, -1);
  // No pose at all.
  const fsw_app::ApproachOutput none = loop.ctl.step(loop.now_us + 10000, nullptr, A::GRIPPER_OPEN);
  assert_true(none.velocity.hold);
  assert_false(none.status.pose_usable);
}

// Frames late (no estimate for more than camera_hold_frames frame
// periods): the manager holds while it flies on the sightings, says since
// when, and flies on once they come back; a stall elsewhere (closing, the
// back-off) flies on the pose alone.
void test_holds_while_frames_are_late_and_resumes(void**) {
  using S = hrp::approach_status_t;
  Loop loop(5);
  loop.run(3.0, A::DEPLOYING);
  assert_false(loop.out.velocity.hold);
  assert_int_equal(loop.out.status.camera, S::CAMERA_STREAMING);
  assert_int_equal(loop.out.status.camera_late_since_utime, -1);
  assert_true(loop.out.status.frame_age_ms >= 0 && loop.out.status.frame_age_ms <= 250);
  const std::int64_t hold_after_us = loop.cfg.camera_hold_frames * loop.cfg.frame_period_us;
  loop.camera_on = false;
  const std::int64_t last_frame_us = loop.ctl_frame_seen();
  // Within the bound: one frame missed is ridden out.
  loop.run(0.4, A::DEPLOYING);
  assert_false(loop.out.velocity.hold);
  assert_int_equal(loop.out.status.camera, S::CAMERA_STREAMING);
  // Past it: hold, from the moment the bound passed.
  loop.run(0.5, A::DEPLOYING);
  std::printf("  frames late: hold %d, frame age %d ms, late since %lld us after the last frame\n",
              loop.out.velocity.hold, loop.out.status.frame_age_ms,
              static_cast<long long>(loop.out.status.camera_late_since_utime - last_frame_us));
  assert_true(loop.out.velocity.hold);
  assert_int_equal(loop.out.status.camera, S::CAMERA_LATE);
  assert_int_equal(loop.out.status.camera_late_since_utime, last_frame_us + hold_after_us);
  assert_true(loop.out.status.frame_age_ms > hold_after_us / 1000);
  for (int k = 0; k < 3; ++k) assert_true(loop.out.velocity.velocity_mps[k] == 0.0);
  loop.run(2.0, A::GRIPPER_OPEN);
  assert_true(loop.out.velocity.hold);
  assert_false(loop.out.status.at_target);
  assert_int_equal(loop.out.status.camera_late_since_utime, last_frame_us + hold_after_us);
  // Keeping station while the fingers close, or backing off, needs the
  // pose only.
  loop.run(0.2, A::CLOSING);
  assert_false(loop.out.velocity.hold);
  assert_int_equal(loop.out.status.camera, S::CAMERA_LATE);
  // Frames again: flies on.
  loop.camera_on = true;
  loop.run(0.5, A::DEPLOYING);
  assert_false(loop.out.velocity.hold);
  assert_int_equal(loop.out.status.camera, S::CAMERA_STREAMING);
  assert_int_equal(loop.out.status.camera_late_since_utime, -1);
  assert_string_equal(fsw_app::to_string(fsw_app::CameraLiveness::kLate), "LATE");
}

// No frame ever (a camera that never started): NOT_SEEN, late since the
// manager's first cycle, and the robot holds.
void test_no_frame_yet_is_not_seen(void**) {
  fsw_app::ApproachConfig cfg;
  fsw_app::ApproachController ctl(cfg, Eigen::Vector3d(0.4, 0.0, 0.0));
  hrp::robot_pose_t pose{};
  pose.source = hrp::robot_pose_t::SOURCE_FILTER;
  pose.T_world_body.quat_wxyz[0] = 1.0;
  pose.utime = 5000000;
  const fsw_app::ApproachOutput out = ctl.step(5000000, &pose, A::DEPLOYING);
  assert_true(out.velocity.hold);
  assert_int_equal(out.status.camera, hrp::approach_status_t::CAMERA_NOT_SEEN);
  assert_int_equal(out.status.camera_late_since_utime, 5000000);
  assert_int_equal(out.status.frame_seen_utime, -1);
  assert_int_equal(out.status.frame_age_ms, -1);
}

}  // namespace

int main() {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_reaches_and_settles_on_the_grasp_pose),
      cmocka_unit_test(test_backs_off_after_letting_go),
      cmocka_unit_test(test_holds_without_a_fresh_filter_pose),
      cmocka_unit_test(test_holds_while_frames_are_late_and_resumes),
      cmocka_unit_test(test_no_frame_yet_is_not_seen),
  };
  return cmocka_run_group_tests(tests, nullptr, nullptr);
}
