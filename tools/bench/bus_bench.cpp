// Google Benchmark: what one message costs the robot's LCM receive path,
// refused or taken, on one core. Run from the build tree:
//   tools/bench/bus_bench --benchmark_repetitions=5 --benchmark_report_aggregates_only=true
//   Refused/BadLength       ARM_STATE with a string length of 0: the walker
//                           refuses it before the decoder
//   Refused/Junk            random bytes on ROBOT_POSE: the fingerprint
//   Refused/ForgedBody      ROBOT_POSE's fingerprint, random body: decoded,
//                           left-over bytes or a range refuses it
//   Refused/ImuCopy         an IMU sample whose counter does not advance
//   Refused/Future          an IMU sample dated 30 s ahead
//   Taken/ArmState          a whole ARM_STATE (four strings), walked, decoded,
//                           checked and swapped into the mailbox
//   Taken/ArmStateUnwalked  the same without the walker: the generated
//                           decoder alone (the old path's decode), for the
//                           walker's own share
//   Taken/RobotPose         a whole ROBOT_POSE into its mailbox
//   Hub/Memq                a junk message through real LCM (memq://):
//                           publish, LCM's dispatch, the hub, the receiver
#include <benchmark/benchmark.h>

#include <random>
#include <vector>

#include "fsw_app/lcm_hub.hpp"
#include "fsw_app/msg_convert.hpp"

namespace {

template <typename Msg>
std::vector<std::uint8_t> encode(const Msg& m) {
  std::vector<std::uint8_t> b(static_cast<std::size_t>(m.getEncodedSize()));
  m.encode(b.data(), 0, static_cast<int>(b.size()));
  return b;
}

hrp::arm_state_t arm_state() {
  hrp::arm_state_t a{};
  a.utime = 1000;
  a.state = hrp::arm_state_t::GRIPPER_OPEN;
  a.state_name = "GRIPPER_OPEN";
  a.fault_name = "NONE";
  a.fault_text = "";
  a.last_reject_name = "ACCEPTED";
  return a;
}

hrp::robot_pose_t robot_pose(std::int64_t utime) {
  hrp::robot_pose_t p{};
  p.utime = utime;
  p.source = hrp::robot_pose_t::SOURCE_FILTER;
  p.T_world_body.quat_wxyz[0] = 1.0;
  return p;
}

template <typename Receiver>
void deliver_loop(benchmark::State& state, Receiver& r, const std::vector<std::uint8_t>& b,
                  std::int64_t now_us) {
  for (auto _ : state) r.deliver(b.data(), static_cast<std::uint32_t>(b.size()), now_us);
  state.SetItemsProcessed(state.iterations());
}

void BM_RefusedBadLength(benchmark::State& state) {
  fsw_app::Mailbox<hrp::arm_state_t> box;
  std::vector<std::uint8_t> b = encode(arm_state());
  b[17] = b[18] = b[19] = b[20] = 0;  // state_name's length: 0
  deliver_loop(state, box, b, 1'000'000);
}

void BM_RefusedJunk(benchmark::State& state) {
  fsw_app::Mailbox<hrp::robot_pose_t> box;
  std::vector<std::uint8_t> b(100);
  std::mt19937 rng(1);
  for (auto& x : b) x = static_cast<std::uint8_t>(rng());
  deliver_loop(state, box, b, 1'000'000);
}

void BM_RefusedForgedBody(benchmark::State& state) {
  fsw_app::Mailbox<hrp::robot_pose_t> box;
  std::vector<std::uint8_t> b = encode(robot_pose(1000));
  std::mt19937 rng(2);
  for (std::size_t k = 8; k < b.size(); ++k) b[k] = static_cast<std::uint8_t>(rng());
  deliver_loop(state, box, b, 1'000'000);
}

void BM_RefusedImuCopy(benchmark::State& state) {
  fsw_app::MessageQueue<hrp::imu_sample_t, 32> q;
  hrp::imu_sample_t s{};
  s.seq = 5;
  s.utime = 1000;
  const std::vector<std::uint8_t> b = encode(s);
  q.deliver(b.data(), static_cast<std::uint32_t>(b.size()), 1'000'000);
  deliver_loop(state, q, b, 1'000'000);
}

void BM_RefusedFuture(benchmark::State& state) {
  fsw_app::MessageQueue<hrp::imu_sample_t, 32> q;
  hrp::imu_sample_t s{};
  s.seq = 5;
  s.utime = 31'000'000;
  deliver_loop(state, q, encode(s), 1'000'000);
}

void BM_TakenArmState(benchmark::State& state) {
  fsw_app::Mailbox<hrp::arm_state_t> box;
  deliver_loop(state, box, encode(arm_state()), fsw_app::kNoReceiverClock);
}

void BM_TakenArmStateUnwalked(benchmark::State& state) {
  hrp::arm_state_t m;
  fsw_app::reserve_text(&m);
  const std::vector<std::uint8_t> b = encode(arm_state());
  for (auto _ : state) {
    benchmark::DoNotOptimize(m.decode(b.data(), 0, static_cast<int>(b.size())));
  }
  state.SetItemsProcessed(state.iterations());
}

void BM_TakenRobotPose(benchmark::State& state) {
  fsw_app::Mailbox<hrp::robot_pose_t> box;
  deliver_loop(state, box, encode(robot_pose(1000)), fsw_app::kNoReceiverClock);
}

void BM_HubMemq(benchmark::State& state) {
  fsw_app::LcmHub hub("memq://");
  fsw_app::Mailbox<hrp::robot_pose_t> box;
  hub.subscribe(fsw_app::channel::kRobotPose, &box);
  std::vector<std::uint8_t> b(100, 0x5a);
  for (auto _ : state) {
    hub.publish_raw(fsw_app::channel::kRobotPose, b.data(), b.size());
    hub.handle(0);
  }
  state.SetItemsProcessed(state.iterations());
}

}  // namespace

BENCHMARK(BM_RefusedBadLength)->Name("Refused/BadLength");
BENCHMARK(BM_RefusedJunk)->Name("Refused/Junk");
BENCHMARK(BM_RefusedForgedBody)->Name("Refused/ForgedBody");
BENCHMARK(BM_RefusedImuCopy)->Name("Refused/ImuCopy");
BENCHMARK(BM_RefusedFuture)->Name("Refused/Future");
BENCHMARK(BM_TakenArmState)->Name("Taken/ArmState");
BENCHMARK(BM_TakenArmStateUnwalked)->Name("Taken/ArmStateUnwalked");
BENCHMARK(BM_TakenRobotPose)->Name("Taken/RobotPose");
BENCHMARK(BM_HubMemq)->Name("Hub/Memq");
BENCHMARK_MAIN();
