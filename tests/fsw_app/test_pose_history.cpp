// The robot's recent poses, over real LCM (memq): a frame's capture time
// between two poses gets the pose interpolated between them (position and
// attitude); a time before the oldest, across a silence in the filter's
// poses, at a lost pose or well after the newest gets none; the ring keeps
// the newest kCapacity; a restarted sender starts it again; a pose not
// from the filter never enters it; and nothing is allocated per pose.
#include <cmath>
#include <vector>

#include "allocation_counter.hpp"
#include "cmocka_cpp.hpp"
#include "fsw_app/lcm_hub.hpp"
#include "fsw_app/msg_convert.hpp"
#include "fsw_app/pose_history.hpp"

namespace {

using fsw_app::PoseAtStatus;
using fsw_app::PoseHistory;

// The robot moving at 0.1 m/s along x and turning at 0.5 rad/s about z.
Eigen::Isometry3d true_pose(std::int64_t t_us) {
  const double t_s = 1e-6 * static_cast<double>(t_us);
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::AngleAxisd(0.5 * t_s, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  T.translation() = Eigen::Vector3d(0.1 * t_s, 0.2, -0.3);
  return T;
}

std::vector<std::uint8_t> encoded_pose(std::int64_t t_us, bool lost = false,
                                       std::int8_t source = hrp::robot_pose_t::SOURCE_FILTER) {
  hrp::robot_pose_t m{};
  m.utime = t_us;
  m.source = source;
  m.lost = lost;
  fsw_app::to_msg(true_pose(t_us), &m.T_world_body);
  std::vector<std::uint8_t> b(static_cast<std::size_t>(m.getEncodedSize()));
  m.encode(b.data(), 0, static_cast<int>(b.size()));
  return b;
}

void give(PoseHistory& h, std::int64_t t_us, bool lost = false) {
  const std::vector<std::uint8_t> b = encoded_pose(t_us, lost);
  h.deliver(b.data(), static_cast<std::uint32_t>(b.size()), fsw_app::kNoReceiverClock);
}

void test_interpolates_between_the_poses_around_a_time(void**) {
  PoseHistory h;
  Eigen::Isometry3d T;
  assert_int_equal(h.pose_at(1'000'000, &T), PoseAtStatus::kNoPose);
  for (std::int64_t t = 1'000'000; t <= 2'000'000; t += 16'000) give(h, t);
  // 1.5 s lies between two poses 16 ms apart: off the true pose by the
  // chord's sag only (well under a micrometre and a microradian here).
  const std::int64_t t = 1'508'000;
  assert_int_equal(h.pose_at(t, &T), PoseAtStatus::kInterpolated);
  const Eigen::Isometry3d truth = true_pose(t);
  assert_true((T.translation() - truth.translation()).norm() < 1e-9);
  assert_true(Eigen::AngleAxisd(T.linear().transpose() * truth.linear()).angle() < 1e-6);
  // Not the newest pose, which is 0.49 s later: 49 mm and 14 deg away.
  Eigen::Isometry3d newest;
  assert_int_equal(h.pose_at(1'992'000, &newest), PoseAtStatus::kNewest);
  assert_true((newest.translation() - T.translation()).norm() > 0.04);
  // Exactly on a held pose.
  assert_int_equal(h.pose_at(1'016'000, &T), PoseAtStatus::kInterpolated);
  assert_true((T.translation() - true_pose(1'016'000).translation()).norm() < 1e-12);
  assert_string_equal(fsw_app::to_string(PoseAtStatus::kInterpolated), "INTERPOLATED");
}

void test_refuses_rather_than_guesses(void**) {
  PoseHistory h;
  Eigen::Isometry3d T;
  for (std::int64_t t = 1'000'000; t <= 1'200'000; t += 16'000) give(h, t);
  const std::int64_t newest = 1'192'000;
  assert_int_equal(h.pose_at(999'999, &T), PoseAtStatus::kTooOld);
  assert_int_equal(h.pose_at(newest + 30'000, &T), PoseAtStatus::kNewest);
  assert_true((T.translation() - true_pose(newest).translation()).norm() < 1e-12);
  assert_int_equal(h.pose_at(newest + PoseHistory::kMaxAhead_us + 1, &T), PoseAtStatus::kTooNew);
  // The filter silent for 0.3 s (an IMU outage): no pose inside the gap.
  give(h, newest + 300'000);
  assert_int_equal(h.pose_at(newest + 150'000, &T), PoseAtStatus::kGap);
  // A lost pose taints the interval on either side of it.
  give(h, newest + 316'000, true);
  give(h, newest + 332'000);
  assert_int_equal(h.pose_at(newest + 310'000, &T), PoseAtStatus::kLost);
  assert_int_equal(h.pose_at(newest + 320'000, &T), PoseAtStatus::kLost);
  assert_int_equal(h.pose_at(newest + 332'000, &T), PoseAtStatus::kNewest);
  assert_string_equal(fsw_app::to_string(PoseAtStatus::kGap), "GAP");
}

void test_keeps_the_newest_and_starts_again_for_a_restarted_sender(void**) {
  PoseHistory h;
  Eigen::Isometry3d T;
  std::int64_t t = 50'000'000;
  for (int k = 0; k < PoseHistory::kCapacity + 40; ++k, t += 16'000) give(h, t);
  assert_int_equal(h.size(), PoseHistory::kCapacity);
  assert_int_equal(h.pose_at(50'000'000 + 39 * 16'000, &T), PoseAtStatus::kTooOld);
  assert_int_equal(h.pose_at(50'000'000 + 41 * 16'000, &T), PoseAtStatus::kInterpolated);
  // A stale copy is refused by the checks and changes nothing.
  give(h, t - 100'000);
  assert_int_equal(h.size(), PoseHistory::kCapacity);
  // The sender restarted: its clock began again, far back.
  give(h, 1'000'000);
  give(h, 1'016'000);
  assert_int_equal(h.size(), 2);
  assert_int_equal(h.pose_at(1'008'000, &T), PoseAtStatus::kInterpolated);
}

void test_only_the_filters_poses_enter_over_lcm(void**) {
  fsw_app::LcmHub hub("memq://");
  assert_true(hub.good());
  PoseHistory h;
  hub.subscribe(fsw_app::channel::kRobotPose, &h);
  const auto send = [&hub](const std::vector<std::uint8_t>& b) {
    hub.publish_raw(fsw_app::channel::kRobotPose, b.data(), b.size());
    hub.handle(100);
  };
  send(encoded_pose(1'000'000));
  send(encoded_pose(1'016'000, false, hrp::robot_pose_t::SOURCE_TRUTH));
  send(encoded_pose(1'032'000));
  assert_int_equal(h.size(), 2);
  assert_int_equal(
      h.input_counts().rejected[static_cast<int>(fsw_app::InputReject::kWrongSource)].load(), 1);
  // Per pose, nothing allocated (the hub's own LCM decoding aside: the
  // history is fed directly here).
  std::vector<std::vector<std::uint8_t>> later;
  for (int k = 0; k < 200; ++k) later.push_back(encoded_pose(2'000'000 + 16'000 * k));
  Eigen::Isometry3d T;
  alloc_counter::arm();
  for (const auto& m : later) {
    h.deliver(m.data(), static_cast<std::uint32_t>(m.size()), fsw_app::kNoReceiverClock);
    (void)h.pose_at(2'000'000 + 16'000 * 100 + 5'000, &T);
  }
  assert_int_equal(alloc_counter::disarm(), 0);
  assert_int_equal(h.pose_at(2'000'000 + 16'000 * 100 + 5'000, &T), PoseAtStatus::kInterpolated);
}

}  // namespace

int main() {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_interpolates_between_the_poses_around_a_time),
      cmocka_unit_test(test_refuses_rather_than_guesses),
      cmocka_unit_test(test_keeps_the_newest_and_starts_again_for_a_restarted_sender),
      cmocka_unit_test(test_only_the_filters_poses_enter_over_lcm),
  };
  return cmocka_run_group_tests(tests, nullptr, nullptr);
}
