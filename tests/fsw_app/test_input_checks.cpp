// Every message a task takes in is decoded aside and checked before it
// changes anything (fsw_app/input_checks.hpp). The reproductions of what
// testing from outside found, each now with the right outcome:
// a truncated ROBOT_POSE kept half-decoded, a NaN pose accepted, a
// PERCH_COMMAND with junk after a valid ABORT carried out, undecodable
// messages counted nowhere.
#include <cmath>
#include <cstring>
#include <limits>
#include <vector>

#include "cmocka_cpp.hpp"
#include "fsw_app/input_health.hpp"
#include "fsw_app/lcm_hub.hpp"

namespace {

using fsw_app::InputReject;

template <typename Msg>
std::vector<std::uint8_t> encode(const Msg& m) {
  std::vector<std::uint8_t> bytes(static_cast<std::size_t>(m.getEncodedSize()));
  assert_int_equal(m.encode(bytes.data(), 0, static_cast<int>(bytes.size())),
                   static_cast<int>(bytes.size()));
  return bytes;
}

hrp::robot_pose_t pose_at(double x_m, std::int64_t utime) {
  hrp::robot_pose_t p{};
  p.utime = utime;
  p.source = hrp::robot_pose_t::SOURCE_FILTER;
  p.T_world_body.position_m[0] = x_m;
  p.T_world_body.quat_wxyz[0] = 1.0;
  return p;
}

std::uint64_t rejected(const fsw_app::InputCounts& c, InputReject r) {
  return c.rejected[static_cast<int>(r)].load();
}

template <typename Msg>
void deliver(fsw_app::Mailbox<Msg>* box, const std::vector<std::uint8_t>& bytes) {
  box->deliver(bytes.data(), static_cast<std::uint32_t>(bytes.size()), fsw_app::kNoReceiverClock);
}

// The last 8 bytes cut; the fingerprint is right.
void test_truncated_pose_changes_nothing(void**) {
  fsw_app::Mailbox<hrp::robot_pose_t> box;
  deliver(&box, encode(pose_at(1.5, 1000)));
  std::vector<std::uint8_t> cut = encode(pose_at(1730.0, 2000));
  cut.resize(cut.size() - 8);
  deliver(&box, cut);
  hrp::robot_pose_t held{};
  assert_int_equal(box.read(&held), 1);
  assert_true(held.T_world_body.position_m[0] == 1.5);
  assert_int_equal(held.utime, 1000);
  assert_int_equal(rejected(box.input_counts(), InputReject::kUndecodable), 1);
  assert_int_equal(box.input_counts().accepted.load(), 1);
}

// Numbers that are not finite, and the ranges.
void test_non_finite_and_impossible_poses_are_refused(void**) {
  fsw_app::Mailbox<hrp::robot_pose_t> box;
  deliver(&box, encode(pose_at(0.5, 1000)));
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  hrp::robot_pose_t p = pose_at(nan, 2000);
  deliver(&box, encode(p));
  p = pose_at(0.6, 2000);
  p.velocity_mps[1] = inf;
  deliver(&box, encode(p));
  p = pose_at(0.6, 2000);
  p.T_world_body.quat_wxyz[1] = nan;
  deliver(&box, encode(p));
  assert_int_equal(rejected(box.input_counts(), InputReject::kNotFinite), 3);

  p = pose_at(0.6, 2000);
  p.T_world_body.quat_wxyz[1] = 1.0;  // norm sqrt(2): not a rotation
  deliver(&box, encode(p));
  p = pose_at(0.6, 2000);
  p.velocity_mps[0] = 100.0;
  deliver(&box, encode(p));
  p = pose_at(5000.0, 2000);
  deliver(&box, encode(p));
  assert_int_equal(rejected(box.input_counts(), InputReject::kOutOfRange), 3);

  hrp::robot_pose_t held{};
  assert_int_equal(box.read(&held), 1);
  assert_true(held.T_world_body.position_m[0] == 0.5);
  // A good one still goes through.
  deliver(&box, encode(pose_at(0.7, 3000)));
  assert_int_equal(box.read(&held), 2);
  assert_true(held.T_world_body.position_m[0] == 0.7);
}

// ROBOT_POSE is the filter's: the truth, the GP's fix or a sender that
// does not say are refused by name, as is a negative variance; none of
// them replaces the filter's pose the tasks fly on.
void test_pose_from_another_source_is_refused(void**) {
  fsw_app::Mailbox<hrp::robot_pose_t> box;
  deliver(&box, encode(pose_at(0.5, 1000)));
  for (std::int8_t source : {hrp::robot_pose_t::SOURCE_TRUTH, hrp::robot_pose_t::SOURCE_GP,
                             hrp::robot_pose_t::SOURCE_UNKNOWN, std::int8_t{42}}) {
    hrp::robot_pose_t p = pose_at(3.0, 2000);
    p.source = source;
    deliver(&box, encode(p));
  }
  assert_int_equal(rejected(box.input_counts(), InputReject::kWrongSource), 4);
  assert_string_equal(fsw_app::to_string(InputReject::kWrongSource), "WRONG_SOURCE");
  hrp::robot_pose_t p = pose_at(3.0, 2000);
  p.pose_covariance[4][4] = -1e-4;
  deliver(&box, encode(p));
  assert_int_equal(rejected(box.input_counts(), InputReject::kOutOfRange), 1);
  hrp::robot_pose_t held{};
  assert_int_equal(box.read(&held), 1);
  assert_true(held.T_world_body.position_m[0] == 0.5);
  p.pose_covariance[4][4] = 1e-4;
  deliver(&box, encode(p));
  assert_int_equal(box.read(&held), 2);
  assert_true(held.T_world_body.position_m[0] == 3.0);
}

// Older than the held one: a reordered or replayed copy. Much older: a
// sender whose clock started again, taken.
void test_stale_messages_are_refused(void**) {
  fsw_app::Mailbox<hrp::robot_pose_t> box;
  deliver(&box, encode(pose_at(0.5, 50'000'000)));
  deliver(&box, encode(pose_at(0.9, 49'000'000)));
  assert_int_equal(rejected(box.input_counts(), InputReject::kStale), 1);
  deliver(&box, encode(pose_at(0.8, 1'000'000)));  // 49 s back: restarted
  hrp::robot_pose_t held{};
  assert_int_equal(box.read(&held), 2);
  assert_true(held.T_world_body.position_m[0] == 0.8);
}

// A valid ABORT with 64 junk bytes after it is not carried
// out; the same ABORT alone is.
void test_command_with_trailing_bytes_is_not_queued(void**) {
  fsw_app::MessageQueue<hrp::perch_command_t, 8> queue;
  hrp::perch_command_t abort{};
  abort.utime = 1;
  abort.sequence = 9;
  abort.command = hrp::perch_command_t::ABORT;
  std::vector<std::uint8_t> bytes = encode(abort);
  const std::size_t whole = bytes.size();
  bytes.resize(whole + 64, 0xA5);
  queue.deliver(bytes.data(), static_cast<std::uint32_t>(bytes.size()), fsw_app::kNoReceiverClock);
  hrp::perch_command_t out{};
  assert_false(queue.pop(&out));
  assert_int_equal(rejected(queue.input_counts(), InputReject::kTrailingBytes), 1);

  abort.tilt_rad = std::numeric_limits<double>::quiet_NaN();
  std::vector<std::uint8_t> nan_bytes = encode(abort);
  queue.deliver(nan_bytes.data(), static_cast<std::uint32_t>(nan_bytes.size()),
                fsw_app::kNoReceiverClock);
  assert_false(queue.pop(&out));
  assert_int_equal(rejected(queue.input_counts(), InputReject::kNotFinite), 1);

  queue.deliver(bytes.data(), static_cast<std::uint32_t>(whole), fsw_app::kNoReceiverClock);
  assert_true(queue.pop(&out));
  assert_int_equal(out.command, hrp::perch_command_t::ABORT);
  assert_int_equal(out.sequence, 9);
}

// Each message type's own ranges.
void test_each_type_has_its_checks(void**) {
  InputReject why = InputReject::kUndecodable;
  hrp::handrail_estimate_t e{};
  e.state = hrp::handrail_estimate_t::STATE_NH;
  assert_true(fsw_app::check_message(e, &why));
  e.state = 7;
  assert_false(fsw_app::check_message(e, &why));
  assert_true(why == InputReject::kOutOfRange);
  e.state = hrp::handrail_estimate_t::STATE_BE;
  e.num_ends = 2;
  for (auto* p : {&e.T_cam_handrail, &e.T_body_handrail, &e.T_body_target}) p->quat_wxyz[0] = 1;
  assert_true(fsw_app::check_message(e, &why));
  e.T_body_target.position_m[2] = std::numeric_limits<double>::quiet_NaN();
  assert_false(fsw_app::check_message(e, &why));
  assert_true(why == InputReject::kNotFinite);

  hrp::body_velocity_command_t v{};
  assert_true(fsw_app::check_message(v, &why));
  v.angular_velocity_rps[2] = -std::numeric_limits<double>::infinity();
  assert_false(fsw_app::check_message(v, &why));

  hrp::arm_state_t a{};
  a.state = hrp::arm_state_t::FAULT + 1;
  assert_false(fsw_app::check_message(a, &why));

  hrp::estimator_health_t h{};
  h.frames_dropped = -5;
  assert_false(fsw_app::check_message(h, &why));

  hrp::approach_status_t s{};
  s.position_error_m = -1.0;
  assert_false(fsw_app::check_message(s, &why));
  s.position_error_m = 0.0;
  s.camera = hrp::approach_status_t::CAMERA_NOT_SEEN + 1;
  assert_false(fsw_app::check_message(s, &why));
}

// Over real LCM (memq): the hub lists each checked channel once, and the
// INPUT_HEALTH message carries the counts by channel and reason.
void test_hub_reports_counts_by_channel(void**) {
  fsw_app::LcmHub hub("memq://");
  assert_true(hub.good());
  fsw_app::Mailbox<hrp::robot_pose_t> pose_a, pose_b;
  fsw_app::MessageQueue<hrp::perch_command_t, 4> commands;
  hub.subscribe(fsw_app::channel::kRobotPose, &pose_a);
  hub.subscribe(fsw_app::channel::kRobotPose, &pose_b);
  hub.subscribe(fsw_app::channel::kPerchCommand, &commands);
  std::size_t n = 0;
  const fsw_app::ChannelInput* inputs = hub.inputs(&n);
  assert_int_equal(n, 2);
  assert_string_equal(inputs[0].channel, "ROBOT_POSE");
  assert_string_equal(inputs[1].channel, "PERCH_COMMAND");

  fsw_app::InputHealthReporter reporter(hub, "manager");
  const std::vector<std::uint8_t> good = encode(pose_at(0.5, 10));
  const std::uint8_t junk[] = {1, 2, 3, 4, 5};
  hub.publish_raw(fsw_app::channel::kRobotPose, good.data(), good.size());
  hub.publish_raw(fsw_app::channel::kRobotPose, junk, sizeof junk);
  hub.publish_raw(fsw_app::channel::kPerchCommand, junk, sizeof junk);
  for (int k = 0; k < 3; ++k) hub.handle(100);

  const hrp::input_health_t& m = reporter.refresh(99);
  assert_int_equal(m.num_channels, 2);
  assert_string_equal(m.tasks.c_str(), "manager");
  assert_string_equal(m.channel[0].c_str(), "ROBOT_POSE");
  assert_int_equal(m.accepted[0], 1);
  const int undecodable = static_cast<int>(InputReject::kUndecodable);
  assert_string_equal(m.reason[undecodable].c_str(), "UNDECODABLE");
  assert_int_equal(m.rejected[0][undecodable], 1);
  assert_int_equal(m.rejected[1][undecodable], 1);
  assert_int_equal(reporter.rejected_total(), 2);
  assert_int_equal(pose_b.input_counts().accepted.load(), 1);  // both receivers judged it
}

}  // namespace

int main() {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_truncated_pose_changes_nothing),
      cmocka_unit_test(test_non_finite_and_impossible_poses_are_refused),
      cmocka_unit_test(test_pose_from_another_source_is_refused),
      cmocka_unit_test(test_stale_messages_are_refused),
      cmocka_unit_test(test_command_with_trailing_bytes_is_not_queued),
      cmocka_unit_test(test_each_type_has_its_checks),
      cmocka_unit_test(test_hub_reports_counts_by_channel),
  };
  return cmocka_run_group_tests(tests, nullptr, nullptr);
}
