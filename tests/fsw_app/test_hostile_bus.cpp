// A second process on the robot's LCM bus during a perch (udpm on
// loopback), sending what testing from outside sent, each with the outcome
// it must have now:
//   - ARM_STATE with a string length of 0 or -1, the arm deployed (it was:
//     std::length_error out of the hub, exit 134, the arm left open):
//     refused as BAD_LENGTH, the perch goes on and perches within 1 cm;
//   - one IMU_SAMPLE dated 30 s ahead (localization froze for 30 s), one
//     ROBOT_POSE dated 9 s ahead (the filter's poses were "stale" for 9 s),
//     one IMU counter jump of 1e15 (reported as a gap of 1e15): refused,
//     perched within 1 cm;
//   - 4 s of copies of the newest IMU sample at ten times the rate, 0.5
//     m/s^2 off (the pose ran 52 m away): refused by their counter,
//     perched within 1 cm;
//   - no robot pose at all mid-approach: the robot holds still and the
//     perch ends POSE_LOST with the arm folded;
//   - a flood of 40,000 junk messages a second for 10 s on the robot's own
//     channels: perched within 1 cm, no arm-loop overrun, every flood
//     message refused and counted by the hub or dropped (and counted) by
//     the kernel before it.
//   argv[1]: the fsw_app program
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <functional>
#include <map>
#include <random>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <lcm/lcm-cpp.hpp>

#include "hil_perch.hpp"
#include "hrp/approach_status_t.hpp"
#include "hrp/arm_state_t.hpp"
#include "hrp/estimator_health_t.hpp"
#include "hrp/gp_pose_t.hpp"
#include "hrp/handrail_estimate_t.hpp"
#include "hrp/imu_sample_t.hpp"
#include "hrp/perch_command_t.hpp"
#include "hrp/robot_pose_t.hpp"

namespace {

using namespace hil_perch;

std::string url_of(int port) {
  return "udpm://239.255.76.67:" + std::to_string(port) + "?ttl=0";
}

// What the other process hears of the robot: the arm's state and the
// newest IMU sample and robot pose, to forge plausible messages from. It
// hears its own malformed messages too, so it decodes as carefully as the
// robot must (LCM's typed subscription would throw on them).
struct Listener {
  std::atomic<int> arm_state{-1};
  hrp::imu_sample_t imu{};
  hrp::robot_pose_t pose{};
  bool have_imu = false, have_pose = false;

  template <typename Msg>
  static bool decode(const lcm::ReceiveBuffer* rbuf, Msg* m) {
    try {
      return m->decode(rbuf->data, 0, static_cast<int>(rbuf->data_size)) ==
             static_cast<int>(rbuf->data_size);
    } catch (...) {
      return false;
    }
  }
  void on_arm(const lcm::ReceiveBuffer* rbuf, const std::string&) {
    hrp::arm_state_t m;
    if (decode(rbuf, &m)) arm_state = m.state;
  }
  void on_imu(const lcm::ReceiveBuffer* rbuf, const std::string&) {
    hrp::imu_sample_t m;
    if (!decode(rbuf, &m) || (have_imu && m.seq <= imu.seq)) return;  // not our copies
    imu = m;
    have_imu = true;
  }
  void on_pose(const lcm::ReceiveBuffer* rbuf, const std::string&) {
    hrp::robot_pose_t m;
    if (decode(rbuf, &m)) {
      pose = m;
      have_pose = true;
    }
  }
  void subscribe(lcm::LCM& lcm) {
    lcm.subscribe("ARM_STATE", &Listener::on_arm, this);
    lcm.subscribe("IMU_SAMPLE", &Listener::on_imu, this);
    lcm.subscribe("ROBOT_POSE", &Listener::on_pose, this);
  }
};

// Handles the bus until the arm reaches `state` (true) or `stop` (false).
bool wait_for_arm(lcm::LCM& lcm, Listener& l, int state, const std::atomic<bool>& stop) {
  while (!stop.load()) {
    lcm.handleTimeout(20);
    if (l.arm_state.load() == state) return true;
  }
  return false;
}

template <typename Msg>
void publish(lcm::LCM& lcm, const char* channel, const Msg& m) {
  const std::vector<std::uint8_t> b = encoded(m);
  lcm.publish(channel, b.data(), static_cast<unsigned>(b.size()));
}

// Runs one perch (approach-iss, `seed`) with `attack` running in a thread
// on the same bus; repeats it when the host stalled a task.
Outcome perch_under(
    int seed, const std::vector<std::string>& extra,
    const std::function<void(const std::string& url, std::atomic<bool>& stop)>& attack,
    const std::function<bool(const Outcome&)>& expected) {
  Outcome o;
  for (int attempt = 0; attempt <= kStallRepeats; ++attempt) {
    const std::string url = url_of(g_port);
    std::atomic<bool> stop{false};
    std::thread peer([&] { attack(url, stop); });
    std::vector<std::string> args = {"--seed", std::to_string(seed)};
    args.insert(args.end(), extra.begin(), extra.end());
    o = run("approach-iss", args);  // on the peer's port
    stop = true;
    peer.join();
    if (expected(o)) break;
    const std::string stall = host_stall(o);
    if (stall.empty()) break;
    std::printf("  NOTE: %s (host); running this case again\n", stall.c_str());
  }
  return o;
}

bool have_udpm() {
  if (!g_udpm) std::printf("  NOTE: needs udpm between processes; not run here\n");
  return g_udpm;
}

void test_malformed_strings_with_the_arm_deployed(void**) {
  if (!have_udpm()) return;
  int sent = 0;
  const Outcome o = perch_under(
      2, {},
      [&sent](const std::string& url, std::atomic<bool>& stop) {
        lcm::LCM lcm(url);
        Listener l;
        l.subscribe(lcm);
        if (!wait_for_arm(lcm, l, hrp::arm_state_t::GRIPPER_OPEN, stop)) return;
        hrp::arm_state_t a{};
        a.state = hrp::arm_state_t::GRIPPER_OPEN;
        std::vector<std::uint8_t> bytes = encoded(a);  // four empty strings: length 1 each
        const std::size_t first_string = 8 + 8 + 1;
        while (!stop.load()) {
          for (std::int32_t len : {0, -1, 0x7fffffff}) {
            for (int k = 0; k < 4; ++k) {
              bytes[first_string + k] =
                  static_cast<std::uint8_t>(static_cast<std::uint32_t>(len) >> (24 - 8 * k));
            }
            lcm.publish("ARM_STATE", bytes.data(), static_cast<unsigned>(bytes.size()));
            ++sent;
          }
          // It hears its own messages: drain, then wait (handleTimeout
          // would return at once on them).
          while (lcm.handleTimeout(0) > 0) {
          }
          std::this_thread::sleep_for(std::chrono::milliseconds(20));
        }
      },
      perched_within_1cm);
  const double refused = input_rejections(o, "ARM_STATE", "BAD_LENGTH");
  std::printf("  ARM_STATE: %d malformed sent, %.0f refused as BAD_LENGTH; exit %d, %s\n", sent,
              refused, o.exit_status, o.text("arm_state").c_str());
  assert_int_equal(o.exit_status, 0);
  assert_true(perched_within_1cm(o));
  assert_true(sent > 30);
  assert_true(refused > 0.9 * sent);
  assert_true(o.number("receiver_faults") == 0.0);
}

void test_dated_ahead_and_jumping_messages(void**) {
  if (!have_udpm()) return;
  const Outcome o = perch_under(
      3, {},
      [](const std::string& url, std::atomic<bool>& stop) {
        lcm::LCM lcm(url);
        Listener l;
        l.subscribe(lcm);
        if (!wait_for_arm(lcm, l, hrp::arm_state_t::GRIPPER_OPEN, stop)) return;
        for (int k = 0; k < 10; ++k) lcm.handleTimeout(20);  // the newest of each
        if (!l.have_imu || !l.have_pose) return;
        hrp::imu_sample_t ahead = l.imu;
        ahead.seq += 1;
        ahead.utime += 30'000'000;
        publish(lcm, "IMU_SAMPLE", ahead);
        hrp::robot_pose_t pose = l.pose;
        pose.utime += 9'000'000;
        pose.T_world_body.position_m[1] += 0.3;
        publish(lcm, "ROBOT_POSE", pose);
        hrp::imu_sample_t jump = l.imu;
        jump.seq += 1'000'000'000'000'000;
        publish(lcm, "IMU_SAMPLE", jump);
      },
      perched_within_1cm);
  std::printf(
      "  IMU_SAMPLE FUTURE %.0f, SEQUENCE %.0f; ROBOT_POSE FUTURE %.0f; imu_seq_gaps %.0f\n",
      input_rejections(o, "IMU_SAMPLE", "FUTURE"), input_rejections(o, "IMU_SAMPLE", "SEQUENCE"),
      input_rejections(o, "ROBOT_POSE", "FUTURE"),
      nested(o, {"localization", "filter", "imu_seq_gaps"}));
  assert_true(perched_within_1cm(o));
  assert_true(input_rejections(o, "IMU_SAMPLE", "FUTURE") >= 1);
  assert_true(input_rejections(o, "IMU_SAMPLE", "SEQUENCE") >= 1);
  assert_true(input_rejections(o, "ROBOT_POSE", "FUTURE") >= 1);
  assert_true(input_rejections(o, "ROBOT_POSE", "STALE") == 0.0);
  assert_true(nested(o, {"localization", "filter", "imu_seq_gaps"}) < 100);
}

void test_copied_imu_samples_are_refused(void**) {
  if (!have_udpm()) return;
  int sent = 0;
  const Outcome o = perch_under(
      4, {},
      [&sent](const std::string& url, std::atomic<bool>& stop) {
        lcm::LCM lcm(url);
        Listener l;
        l.subscribe(lcm);
        if (!wait_for_arm(lcm, l, hrp::arm_state_t::GRIPPER_OPEN, stop)) return;
        const auto t0 = std::chrono::steady_clock::now();
        while (!stop.load() && std::chrono::steady_clock::now() - t0 < std::chrono::seconds(4)) {
          lcm.handleTimeout(0);
          if (!l.have_imu) continue;
          hrp::imu_sample_t copy = l.imu;  // the newest, its counter unchanged
          copy.a_body_mps2[0] += 0.5;
          publish(lcm, "IMU_SAMPLE", copy);
          ++sent;
          std::this_thread::sleep_for(std::chrono::microseconds(1600));  // 625 Hz
        }
      },
      perched_within_1cm);
  const double refused = input_rejections(o, "IMU_SAMPLE", "SEQUENCE");
  std::printf("  IMU copies: %d sent, %.0f refused (SEQUENCE); IMU propagated %.0f\n", sent,
              refused, nested(o, {"localization", "filter", "imu_propagated"}));
  assert_true(perched_within_1cm(o));
  assert_true(sent > 1000);
  assert_true(refused > 0.95 * sent);
}

void test_no_pose_mid_approach_holds_then_folds(void**) {
  const Outcome o = run_expecting("approach-iss", {"--seed", "5", "--fault", "imu-lost@2"},
                                  [](const Outcome& r) { return r.text("fault") == "POSE_LOST"; });
  std::printf("  arm %.3f / %.3f rad at the end\n", o.number("arm_tilt_rad"),
              o.number("arm_pan_rad"));
  assert_string_equal(o.text("fault").c_str(), "POSE_LOST");
  assert_string_equal(o.text("arm_state").c_str(), "FAULT");
  assert_false(o.flag("perched"));
  assert_true(o.exit_status != 0);
  // Folded: the stow posture (90, 0 deg in fsw_app.json).
  assert_true(std::fabs(o.number("arm_tilt_rad") - M_PI / 2) < 0.05);
  assert_true(std::fabs(o.number("arm_pan_rad")) < 0.05);
}

// UDP datagrams the kernel dropped for full receive buffers, host-wide.
long long udp_receive_buffer_drops() {
  std::ifstream f("/proc/net/snmp");
  std::string line, header;
  while (std::getline(f, line)) {
    if (line.rfind("Udp:", 0) != 0) continue;
    if (header.empty()) {
      header = line;
      continue;
    }
    std::istringstream h(header), v(line);
    std::string name, value;
    while (h >> name && v >> value) {
      if (name == "RcvbufErrors") return std::stoll(value);
    }
  }
  return -1;
}

// The flood: junk on each channel the robot reads, half of it behind the
// channel type's own fingerprint (so that it reaches the decoder), some of
// it ARM_STATE with a string length of 0.
struct Flood {
  std::map<std::string, long long> sent;
  long long total = 0;
};

template <typename Msg>
std::uint64_t fingerprint() {
  return static_cast<std::uint64_t>(Msg::getHash());
}

void flood(const std::string& url, std::atomic<bool>& stop, double per_s, double seconds,
           Flood* out) {
  {
    // Listen until the perch starts, then close the listening socket: during
    // the flood only the robot's own socket receives, so the kernel's drop
    // count is the robot's.
    lcm::LCM listen(url);
    Listener l;
    l.subscribe(listen);
    if (!wait_for_arm(listen, l, hrp::arm_state_t::DEPLOYING, stop)) return;
  }
  lcm::LCM lcm(url);  // publishes only: no receive socket
  const std::vector<std::pair<const char*, std::uint64_t>> channels = {
      {"ROBOT_POSE", fingerprint<hrp::robot_pose_t>()},
      {"IMU_SAMPLE", fingerprint<hrp::imu_sample_t>()},
      {"GP_POSE", fingerprint<hrp::gp_pose_t>()},
      {"HANDRAIL_ESTIMATE", fingerprint<hrp::handrail_estimate_t>()},
      {"PERCH_COMMAND", fingerprint<hrp::perch_command_t>()},
      {"APPROACH_STATUS", fingerprint<hrp::approach_status_t>()},
      {"ARM_STATE", fingerprint<hrp::arm_state_t>()},
      {"ESTIMATOR_HEALTH", fingerprint<hrp::estimator_health_t>()}};
  std::mt19937 rng(1234);
  std::uint8_t buf[160];
  const auto t0 = std::chrono::steady_clock::now();
  const auto period = std::chrono::microseconds(1000);
  const int per_tick = static_cast<int>(per_s / 1000.0);
  auto next = t0;
  while (!stop.load() &&
         std::chrono::steady_clock::now() - t0 < std::chrono::duration<double>(seconds)) {
    for (int k = 0; k < per_tick; ++k) {
      const auto& [channel, hash] = channels[rng() % channels.size()];
      const std::size_t size = 8 + rng() % 120;
      for (std::size_t i = 0; i < size; ++i) buf[i] = static_cast<std::uint8_t>(rng());
      if (rng() % 2 == 0) {
        for (int i = 0; i < 8; ++i) buf[i] = static_cast<std::uint8_t>(hash >> (56 - 8 * i));
        if (std::string(channel) == "ARM_STATE" && size > 21) {
          buf[17] = buf[18] = buf[19] = buf[20] = 0;  // state_name length 0
        }
      }
      lcm.publish(channel, buf, static_cast<unsigned>(size));
      ++out->sent[channel];
      ++out->total;
    }
    next += period;
    std::this_thread::sleep_until(next);
  }
}

void test_flood_on_the_robots_own_bus(void**) {
  if (!have_udpm()) return;
  constexpr double kPerS = 40000.0, kSeconds = 10.0;
  Flood f;
  long long drops_before = 0, drops = 0;
  double wall_s = 0.0;
  const Outcome o = perch_under(
      6, {},
      [&](const std::string& url, std::atomic<bool>& stop) {
        f = Flood{};
        drops_before = udp_receive_buffer_drops();
        const auto t0 = std::chrono::steady_clock::now();
        flood(url, stop, kPerS, kSeconds, &f);
        wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      },
      [](const Outcome& r) { return perched_within_1cm(r) && r.number("arm_overruns") == 0.0; });
  drops = udp_receive_buffer_drops() - drops_before;
  double refused = 0.0;
  for (const auto& [channel, n] : f.sent) {
    const formats::JsonValue* in = o.json.find("inputs");
    const formats::JsonValue* c = in ? in->find(channel) : nullptr;
    const formats::JsonValue* r = c ? c->find("rejected") : nullptr;
    double ch = 0.0;
    if (r) {
      for (const auto& [reason, v] : r->members) ch += v.number;
    }
    std::printf("  %-17s %lld sent, %.0f refused\n", channel.c_str(), n, ch);
    refused += ch;
  }
  std::printf(
      "  flood: %lld messages in %.1f s (%.0f/s); %.0f refused by the hub, %lld dropped by the "
      "kernel; grasp %.1f mm, arm loop %.0f overruns, longest cycle gap %.0f ms\n",
      f.total, wall_s, f.total / std::max(wall_s, 1e-3), refused, drops,
      1e3 * o.number("grasp_error_m"), o.number("arm_overruns"), o.number("arm_longest_gap_ms"));
  assert_true(perched_within_1cm(o));
  assert_true(o.number("arm_overruns") == 0.0);
  assert_true(f.total > 0.8 * kPerS * kSeconds);
  // Every flood message that reached the hub was refused and counted; the
  // rest were dropped before it: by the kernel (its count is above) or by
  // LCM's own receive queue (2000 buffers, which counts nowhere), a few
  // hundred in 400,000 here.
  assert_true(refused <= static_cast<double>(f.total));
  assert_true(refused + static_cast<double>(drops) >= 0.995 * static_cast<double>(f.total));
  assert_true(o.number("receiver_faults") == 0.0);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: %s FSW_APP [TEST_NAME_PATTERN]\n", argv[0]);
    return 2;
  }
  hil_perch::init(argv[1]);
  if (argc > 2) cmocka_set_test_filter(argv[2]);  // e.g. "*flood*"
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_malformed_strings_with_the_arm_deployed),
      cmocka_unit_test(test_dated_ahead_and_jumping_messages),
      cmocka_unit_test(test_copied_imu_samples_are_refused),
      cmocka_unit_test(test_no_pose_mid_approach_holds_then_folds),
      cmocka_unit_test(test_flood_on_the_robots_own_bus),
  };
  return cmocka_run_group_tests(tests, nullptr, nullptr);
}
