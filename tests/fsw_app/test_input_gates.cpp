// Messages judged against the receiver's own clock and the channel's
// history (fsw_app/input_gates.hpp). Each case found from outside during a
// perch, with the outcome it must have now:
//   - one IMU_SAMPLE dated 30 s ahead froze localization for 30 s (every
//     real sample after it "out of order"): refused, the real ones taken;
//   - one ROBOT_POSE dated 9 s ahead made the filter's poses "stale" for
//     9 s: refused, the real ones taken;
//   - copies of the newest IMU sample at ten times the rate were all
//     propagated: refused by their counter;
//   - a counter jump of 1e15 was taken and reported as a gap of 1e15;
//   - nothing bounded a channel's rate.
#include <vector>

#include "cmocka_cpp.hpp"
#include "fsw_app/lcm_hub.hpp"

namespace {

using fsw_app::InputReject;

template <typename Msg>
std::vector<std::uint8_t> encode(const Msg& m) {
  std::vector<std::uint8_t> bytes(static_cast<std::size_t>(m.getEncodedSize()));
  m.encode(bytes.data(), 0, static_cast<int>(bytes.size()));
  return bytes;
}

std::uint64_t rejected(const fsw_app::InputCounts& c, InputReject r) {
  return c.rejected[static_cast<int>(r)].load();
}

constexpr std::int64_t kNow_us = 100'000'000;  // the receiver's clock: 100 s
constexpr std::int64_t kImuPeriod_us = 16'000;

hrp::imu_sample_t imu(std::int64_t seq, std::int64_t utime) {
  hrp::imu_sample_t s{};
  s.seq = seq;
  s.utime = utime;
  s.a_body_mps2[0] = 0.01;
  return s;
}

using ImuQueue = fsw_app::MessageQueue<hrp::imu_sample_t, 64>;

void deliver(ImuQueue* q, const hrp::imu_sample_t& s, std::int64_t now_us) {
  const std::vector<std::uint8_t> b = encode(s);
  q->deliver(b.data(), static_cast<std::uint32_t>(b.size()), now_us);
}

std::size_t drain(ImuQueue* q) {
  hrp::imu_sample_t out;
  std::size_t n = 0;
  while (q->pop(&out)) ++n;
  return n;
}

void test_imu_dated_ahead_is_refused_and_the_real_ones_pass(void**) {
  ImuQueue q;
  std::int64_t now = kNow_us;
  deliver(&q, imu(1, now), now);
  deliver(&q, imu(2, now + 30'000'000), now);  // plausible, 30 s ahead
  for (std::int64_t k = 2; k < 40; ++k) {
    now += kImuPeriod_us;
    deliver(&q, imu(k, now), now);
  }
  assert_int_equal(rejected(q.input_counts(), InputReject::kFuture), 1);
  assert_int_equal(q.input_counts().accepted.load(), 39);
  assert_int_equal(drain(&q), 39);
  // Within the stated tolerance (a sender stamps just before it sends).
  deliver(&q, imu(40, now + fsw_app::kMaxAheadOfReceiver_us / 2), now);
  assert_int_equal(q.input_counts().accepted.load(), 40);
}

void test_pose_dated_ahead_cannot_make_the_real_ones_stale(void**) {
  fsw_app::Mailbox<hrp::robot_pose_t> box;
  hrp::robot_pose_t p{};
  p.T_world_body.quat_wxyz[0] = 1.0;
  p.source = hrp::robot_pose_t::SOURCE_FILTER;
  std::int64_t now = kNow_us;
  p.utime = now + 9'000'000;
  p.T_world_body.position_m[0] = 5.0;  // the forged one
  std::vector<std::uint8_t> b = encode(p);
  box.deliver(b.data(), static_cast<std::uint32_t>(b.size()), now);
  p.T_world_body.position_m[0] = 0.5;
  for (int k = 0; k < 50; ++k) {
    now += kImuPeriod_us;
    p.utime = now;
    b = encode(p);
    box.deliver(b.data(), static_cast<std::uint32_t>(b.size()), now);
  }
  assert_int_equal(rejected(box.input_counts(), InputReject::kFuture), 1);
  assert_int_equal(rejected(box.input_counts(), InputReject::kStale), 0);
  hrp::robot_pose_t held{};
  assert_int_equal(box.read(&held), 50);
  assert_true(held.T_world_body.position_m[0] == 0.5);
}

// A burst of copies of the newest sample (the same counter), at ten times
// the IMU's rate: none reaches the filter.
void test_imu_copies_are_refused_by_their_counter(void**) {
  ImuQueue q;
  std::int64_t now = kNow_us;
  deliver(&q, imu(7, now), now);
  hrp::imu_sample_t copy = imu(7, now);
  copy.a_body_mps2[0] += 0.5;
  for (int k = 0; k < 250; ++k) {
    now += kImuPeriod_us / 10;
    deliver(&q, copy, now);
  }
  assert_int_equal(rejected(q.input_counts(), InputReject::kSequence), 250);
  assert_int_equal(drain(&q), 1);
  deliver(&q, imu(8, now), now);
  assert_int_equal(drain(&q), 1);
}

// A jump of 1e15 is refused; a sender that restarted (counting up from 0)
// is followed after kSequenceResyncRun samples; copies never are.
void test_counter_jumps_are_bounded_and_a_restart_is_followed(void**) {
  ImuQueue q;
  std::int64_t now = kNow_us;
  deliver(&q, imu(5000, now), now);
  deliver(&q, imu(5000 + 1'000'000'000'000'000, now), now);
  assert_int_equal(rejected(q.input_counts(), InputReject::kSequence), 1);
  deliver(&q, imu(5001 + fsw_app::kMaxSequenceJump, now), now);  // one past the bound
  assert_int_equal(rejected(q.input_counts(), InputReject::kSequence), 2);
  deliver(&q, imu(5000 + fsw_app::kMaxSequenceJump, now), now);  // at the bound
  assert_int_equal(q.input_counts().accepted.load(), 2);
  drain(&q);
  for (int k = 0; k < fsw_app::kSequenceResyncRun; ++k) {
    now += kImuPeriod_us;
    deliver(&q, imu(k, now), now);
  }
  assert_int_equal(drain(&q), 1);  // the run's last sample, and every one after it
  now += kImuPeriod_us;
  deliver(&q, imu(fsw_app::kSequenceResyncRun, now), now);
  assert_int_equal(drain(&q), 1);
}

// Counters at the top of their range (a fuzzer's find: a run of refused
// samples ending at INT64_MAX overflowed the restart test).
void test_counters_at_the_end_of_their_range(void**) {
  ImuQueue q;
  deliver(&q, imu(5, kNow_us), kNow_us);
  deliver(&q, imu(INT64_MAX, kNow_us), kNow_us);
  deliver(&q, imu(INT64_MAX, kNow_us), kNow_us);
  deliver(&q, imu(0, kNow_us), kNow_us);
  assert_int_equal(rejected(q.input_counts(), InputReject::kSequence), 3);
  deliver(&q, imu(6, kNow_us), kNow_us);
  assert_int_equal(q.input_counts().accepted.load(), 2);
}

// Valid-looking samples far above the bound: the excess is refused and
// counted; at the IMU's own rate nothing is.
void test_rate_bound(void**) {
  ImuQueue q;
  std::int64_t now = kNow_us;
  std::size_t taken = 0;
  for (int k = 1; k <= 2000; ++k) {
    now += 500;  // 2 kHz for one second
    deliver(&q, imu(k, now), now);
    taken += drain(&q);
  }
  const auto bound = fsw_app::rate_bound(static_cast<const hrp::imu_sample_t*>(nullptr));
  std::printf(
      "  2000 samples in 1 s: %zu taken (bound %.0f/s, burst %.0f), %llu refused\n", taken,
      bound.max_per_s, bound.burst,
      static_cast<unsigned long long>(rejected(q.input_counts(), InputReject::kRateLimited)));
  assert_true(taken <= static_cast<std::size_t>(bound.max_per_s + bound.burst) + 1);
  assert_true(taken >= static_cast<std::size_t>(bound.max_per_s));
  assert_int_equal(rejected(q.input_counts(), InputReject::kRateLimited) + taken, 2000);

  ImuQueue steady;
  for (int k = 1; k <= 625; ++k) {
    now += kImuPeriod_us;
    deliver(&steady, imu(k, now), now);
    drain(&steady);
  }
  assert_int_equal(steady.input_counts().accepted.load(), 625);
}

// Refused messages take no token: a flood of junk and copies cannot starve
// the real stream.
void test_refused_messages_take_no_token(void**) {
  ImuQueue q;
  std::int64_t now = kNow_us;
  const std::uint8_t junk[] = {1, 2, 3, 4};
  deliver(&q, imu(0, now), now);
  assert_int_equal(drain(&q), 1);
  std::size_t real = 0;
  for (int k = 1; k <= 300; ++k) {
    now += kImuPeriod_us;
    for (int j = 0; j < 100; ++j) {
      q.deliver(junk, sizeof junk, now);
      deliver(&q, imu(k - 1, now), now);  // a copy of the last one
    }
    deliver(&q, imu(k, now), now);
    real += drain(&q);
  }
  assert_int_equal(real, 300);
  assert_int_equal(rejected(q.input_counts(), InputReject::kRateLimited), 0);
}

// A replay's hub judges neither time nor rate (its messages are dated in
// the past's clock), but still counters.
void test_replay_judges_counters_only(void**) {
  ImuQueue q;
  for (int k = 1; k <= 1000; ++k)
    deliver(&q, imu(k, kNow_us + 1'000'000'000), fsw_app::kNoReceiverClock);
  deliver(&q, imu(1000, kNow_us), fsw_app::kNoReceiverClock);
  assert_int_equal(q.input_counts().accepted.load(), 1000);
  assert_int_equal(rejected(q.input_counts(), InputReject::kSequence), 1);
}

}  // namespace

int main() {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_imu_dated_ahead_is_refused_and_the_real_ones_pass),
      cmocka_unit_test(test_pose_dated_ahead_cannot_make_the_real_ones_stale),
      cmocka_unit_test(test_imu_copies_are_refused_by_their_counter),
      cmocka_unit_test(test_counter_jumps_are_bounded_and_a_restart_is_followed),
      cmocka_unit_test(test_counters_at_the_end_of_their_range),
      cmocka_unit_test(test_rate_bound),
      cmocka_unit_test(test_refused_messages_take_no_token),
      cmocka_unit_test(test_replay_judges_counters_only),
  };
  return cmocka_run_group_tests(tests, nullptr, nullptr);
}
