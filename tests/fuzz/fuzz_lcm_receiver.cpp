// libFuzzer: fsw_app's receive path for one LCM message type, as the robot
// subscribes to it (a Mailbox or a MessageQueue from lcm_hub.hpp): the
// length-field walk, the generated decoder, the content checks, then the
// time, sequence and rate gates. Whatever arrives on the bus ends up there,
// so no bytes may read out of bounds, throw past the receiver or leave it
// holding a message that would not pass its own checks.
//
// Built once per type: -DFUZZ_TYPE_arm_state_t (the one with strings),
// robot_pose_t, handrail_estimate_t, approach_status_t, estimator_health_t
// (Mailboxes), perch_command_t, imu_sample_t, gp_pose_t (MessageQueues of
// the robot's capacities).
//
// Input: a selector byte, then the message.
//   bit 7: 1 = the bytes are the message as it is (fingerprint included,
//          as a log holds it); 0 = the type's fingerprint is put in front.
//   bit 6: 1 = six more bytes follow, the receiver's clock (big-endian
//          microseconds, 48 bits: a monotonic clock's range); 0 = a replay
//          receiver (kNoReceiverClock).
//   bit 5: queues only: 1 = leave what was queued; 0 = drain the queue.
// One receiver lives across inputs, as on the robot, so the held message,
// the sequence and rate gates and the queue carry over. Each input is
// delivered twice. A model of what the receiver should hold (the bytes of
// the held message, or of each queued one) is kept beside it and compared
// after every delivery. A saved crash may need a message held before it:
// replay it after a seed, e.g. fuzz_arm_state_t SEED CRASH.
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <deque>
#include <string>
#include <type_traits>
#include <vector>

#include "fsw_app/input_checks.hpp"
#include "fsw_app/lcm_hub.hpp"
#include "fsw_app/wire_check.hpp"

namespace {

// The receivers of fsw_app/src and fsw_app/include (capacity 0: a Mailbox).
#if defined(FUZZ_TYPE_arm_state_t)
using Msg = hrp::arm_state_t;
constexpr std::size_t kCapacity = 0;  // perch_manager.hpp, run_watch.hpp
#elif defined(FUZZ_TYPE_robot_pose_t)
using Msg = hrp::robot_pose_t;
constexpr std::size_t kCapacity = 0;  // perch_manager.hpp, estimator_task.hpp
#elif defined(FUZZ_TYPE_handrail_estimate_t)
using Msg = hrp::handrail_estimate_t;
constexpr std::size_t kCapacity = 0;  // perch_manager.hpp, localization_task.hpp
#elif defined(FUZZ_TYPE_approach_status_t)
using Msg = hrp::approach_status_t;
constexpr std::size_t kCapacity = 0;  // arm_task.hpp, run_watch.hpp
#elif defined(FUZZ_TYPE_estimator_health_t)
using Msg = hrp::estimator_health_t;
constexpr std::size_t kCapacity = 0;  // run_watch.hpp
#elif defined(FUZZ_TYPE_perch_command_t)
using Msg = hrp::perch_command_t;
constexpr std::size_t kCapacity = 8;  // arm_task.hpp: kCommandQueue
#elif defined(FUZZ_TYPE_imu_sample_t)
using Msg = hrp::imu_sample_t;
constexpr std::size_t kCapacity = 32;  // localization_task.hpp
#elif defined(FUZZ_TYPE_gp_pose_t)
using Msg = hrp::gp_pose_t;
constexpr std::size_t kCapacity = 4;  // localization_task.hpp
#else
#error "define one FUZZ_TYPE_<type>, e.g. -DFUZZ_TYPE_arm_state_t"
#endif

constexpr bool kIsQueue = kCapacity > 0;
using Receiver =
    std::conditional_t<kIsQueue, fsw_app::MessageQueue<Msg, (kIsQueue ? kCapacity : 1)>,
                       fsw_app::Mailbox<Msg>>;

using Bytes = std::vector<std::uint8_t>;

// An invariant that failed: named on stderr, then the crash libFuzzer saves.
#define CHECK(cond)                                                                          \
  do {                                                                                       \
    if (!(cond)) {                                                                           \
      std::fprintf(stderr, "fuzz_lcm_receiver.cpp:%d: CHECK(%s) failed\n", __LINE__, #cond); \
      std::abort();                                                                          \
    }                                                                                        \
  } while (false)

// Type-specific promises beyond check_message. A string is an LCM string:
// within the wire limit, and no NUL before its terminator (the generated
// encoder measures it with strlen, its getEncodedSize with size()).
void check_fields(const hrp::arm_state_t& m) {
  for (const std::string* s : {&m.state_name, &m.fault_name, &m.fault_text, &m.last_reject_name}) {
    CHECK(s->size() <= fsw_app::kMaxWireStringBytes);
    CHECK(s->find('\0') == std::string::npos);
  }
}
template <typename M>
void check_fields(const M&) {}

// A message a receiver handed out: it passes the checks again and
// re-encodes to exactly the bytes it came from.
void check_held(const Msg& m, const Bytes& delivered) {
  fsw_app::InputReject why = fsw_app::InputReject::kUndecodable;
  CHECK(fsw_app::check_message(m, &why));
  check_fields(m);
  const int n = m.getEncodedSize();
  CHECK(n >= 0 && static_cast<std::size_t>(n) == delivered.size());
  Bytes again(delivered.size() + 1);
  CHECK(m.encode(again.data(), 0, static_cast<int>(again.size())) == n);
  CHECK(std::memcmp(again.data(), delivered.data(), delivered.size()) == 0);
}

std::uint64_t total(const fsw_app::InputCounts& c) {
  return c.accepted.load() + c.rejected_total();
}

// The receiver and its model.
Receiver the_receiver;
Bytes held_bytes;             // Mailbox: the held message's bytes
std::deque<Bytes> queued;     // MessageQueue: the queued messages' bytes, oldest first
std::uint64_t overflows = 0;  // MessageQueue: the oldest overwritten

// A template, so that only the branch of the receiver's kind is compiled.
template <typename R>
void deliver(R& receiver, const Bytes& bytes, std::int64_t now_us) {
  const fsw_app::InputCounts& counts = receiver.input_counts();
  const std::uint64_t before = total(counts);
  const std::uint64_t accepted_before = counts.accepted.load();
  if constexpr (kIsQueue) {
    receiver.deliver(bytes.data(), static_cast<std::uint32_t>(bytes.size()), now_us);
    CHECK(total(counts) == before + 1);
    if (counts.accepted.load() != accepted_before) {
      CHECK(counts.accepted.load() == accepted_before + 1);
      if (queued.size() == kCapacity) {
        queued.pop_front();
        ++overflows;
      }
      queued.push_back(bytes);
    }
    CHECK(receiver.overflows() == overflows);
  } else {
    const std::uint64_t seq_before = receiver.sequence();
    receiver.deliver(bytes.data(), static_cast<std::uint32_t>(bytes.size()), now_us);
    CHECK(total(counts) == before + 1);
    Msg held;
    const std::uint64_t seq = receiver.read(&held);
    const bool accepted = counts.accepted.load() != accepted_before;
    if (accepted) {
      CHECK(counts.accepted.load() == accepted_before + 1 && seq == seq_before + 1);
      held_bytes = bytes;
    } else {
      CHECK(seq == seq_before);
    }
    // Taken or not, what it holds is the last message it took, intact.
    if (seq != 0) check_held(held, held_bytes);
  }
}

template <typename R>
void drain(R& receiver) {
  Msg out;
  while (!queued.empty()) {
    CHECK(receiver.pop(&out));
    check_held(out, queued.front());
    queued.pop_front();
  }
  CHECK(!receiver.pop(&out));
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const std::uint8_t selector = data[0];
  std::size_t pos = 1;
  std::int64_t now_us = fsw_app::kNoReceiverClock;
  if ((selector & 0x40) != 0) {
    if (size < pos + 6) return 0;
    std::uint64_t t = 0;
    for (int k = 0; k < 6; ++k) t = (t << 8) | data[pos++];
    now_us = static_cast<std::int64_t>(t);
  }
  Bytes bytes;
  if ((selector & 0x80) == 0) {
    const auto hash = static_cast<std::uint64_t>(Msg::getHash());
    for (int k = 7; k >= 0; --k) bytes.push_back(static_cast<std::uint8_t>(hash >> (8 * k)));
  }
  bytes.insert(bytes.end(), data + pos, data + size);
  if (bytes.size() > UINT32_MAX) return 0;
  deliver(the_receiver, bytes, now_us);
  deliver(the_receiver, bytes, now_us);
  if constexpr (kIsQueue) {
    if ((selector & 0x20) == 0) drain(the_receiver);
  }
  return 0;
}
