// Length fields the generated decoders must never see. Testing from outside
// found that one ARM_STATE with a string length of 0 (LCM's decoder calls
// assign(p, len - 1)) threw std::length_error out of the hub and killed
// fsw_app with the arm deployed. Here every string and array length field
// of every message type with one (arm_state_t, input_health_t,
// depth_frame_t) is set to 0, -1, one past the limit, past the end of the
// bytes, INT32_MIN and INT32_MAX and sent over real LCM (memq) to the
// receiver the robot uses: each is refused and counted as BAD_LENGTH, the
// held message stays, nothing escapes. The field offsets are found in the
// generated encoder's own bytes, not from the walker's layout.
#include <climits>
#include <cstring>
#include <stdexcept>
#include <string>
#include <vector>

#include "cmocka_cpp.hpp"
#include "fsw_app/depth_frame_msg.hpp"
#include "fsw_app/lcm_hub.hpp"
#include "fsw_app/msg_convert.hpp"
#include "fsw_app/wire_check.hpp"

namespace {

using fsw_app::InputReject;

template <typename Msg>
std::vector<std::uint8_t> encode(const Msg& m) {
  std::vector<std::uint8_t> bytes(static_cast<std::size_t>(m.getEncodedSize()));
  assert_int_equal(m.encode(bytes.data(), 0, static_cast<int>(bytes.size())),
                   static_cast<int>(bytes.size()));
  return bytes;
}

std::int32_t read_be32(const std::vector<std::uint8_t>& b, std::size_t at) {
  return static_cast<std::int32_t>((std::uint32_t{b[at]} << 24) | (std::uint32_t{b[at + 1]} << 16) |
                                   (std::uint32_t{b[at + 2]} << 8) | std::uint32_t{b[at + 3]});
}

void write_be32(std::vector<std::uint8_t>* b, std::size_t at, std::int32_t v) {
  const auto u = static_cast<std::uint32_t>(v);
  for (int k = 0; k < 4; ++k) (*b)[at + k] = static_cast<std::uint8_t>(u >> (24 - 8 * k));
}

// Where the int32 length of the string holding `text` sits in the bytes.
std::size_t string_length_at(const std::vector<std::uint8_t>& b, const std::string& text) {
  const std::string needle = text + '\0';
  for (std::size_t at = 4; at + needle.size() <= b.size(); ++at) {
    if (std::memcmp(b.data() + at, needle.data(), needle.size()) == 0 &&
        read_be32(b, at - 4) == static_cast<std::int32_t>(needle.size())) {
      return at - 4;
    }
  }
  fail_msg("no string \"%s\" in the encoded message", text.c_str());
  return 0;
}

struct LengthField {
  std::string name;
  std::size_t at;      // offset of the int32
  std::int32_t limit;  // the largest value a receiver takes
};

// The values each field is set to, with what they stand for.
std::vector<std::pair<std::int32_t, std::string>> bad_values(const LengthField& f,
                                                             std::size_t size) {
  const std::int32_t past_end = static_cast<std::int32_t>(size - f.at);  // beyond the bytes left
  return {{0, "0"},
          {-1, "-1"},
          {f.limit + 1, "one past the limit"},
          {past_end, "past the end of the bytes"},
          {INT32_MIN, "INT32_MIN"},
          {INT32_MAX, "INT32_MAX"}};
}

// Sends each bad value of each field through the hub to `box`; every one is
// refused as BAD_LENGTH and the good message stays held.
template <typename Msg>
void each_bad_length_is_refused(const char* channel, const std::vector<std::uint8_t>& good,
                                const std::vector<LengthField>& fields, bool strings_end_zero) {
  fsw_app::LcmHub hub("memq://");
  assert_true(hub.good());
  fsw_app::Mailbox<Msg> box;
  hub.subscribe(channel, &box);
  hub.publish_raw(channel, good.data(), good.size());
  assert_true(hub.handle(100) > 0);
  assert_int_equal(box.input_counts().accepted.load(), 1);
  std::uint64_t sent = 0;
  for (const LengthField& f : fields) {
    for (const auto& [value, what] : bad_values(f, good.size())) {
      if (value == 0 && !strings_end_zero) continue;  // an empty array is a good one
      std::vector<std::uint8_t> bytes = good;
      write_be32(&bytes, f.at, value);
      const fsw_app::WireFault fault =
          fsw_app::wire_check(static_cast<const Msg*>(nullptr), bytes.data(), bytes.size());
      std::printf("  %s %s = %d (%s): %s\n", channel, f.name.c_str(), value, what.c_str(),
                  fsw_app::to_string(fault));
      assert_true(fault != fsw_app::WireFault::kNone);
      hub.publish_raw(channel, bytes.data(), bytes.size());
      assert_true(hub.handle(100) > 0);
      ++sent;
      assert_int_equal(
          box.input_counts().rejected[static_cast<int>(InputReject::kBadLength)].load(), sent);
    }
  }
  assert_int_equal(box.input_counts().accepted.load(), 1);
  assert_int_equal(box.input_counts().rejected_total(), sent);
  assert_int_equal(hub.receiver_faults(), 0);
  Msg held;
  assert_int_equal(box.read(&held), 1);
}

hrp::arm_state_t arm_state() {
  hrp::arm_state_t a{};
  a.utime = 1000;
  a.state = hrp::arm_state_t::GRIPPER_OPEN;
  a.state_name = "GRIPPER_OPEN";
  a.fault_name = "NONE";
  a.fault_text = "no fault text";
  a.last_reject_name = "ACCEPTED";
  return a;
}

void test_arm_state_lengths(void**) {
  const std::vector<std::uint8_t> good = encode(arm_state());
  const auto limit = static_cast<std::int32_t>(fsw_app::kMaxWireStringBytes + 1);
  std::vector<LengthField> fields;
  for (const char* s : {"GRIPPER_OPEN", "NONE", "no fault text", "ACCEPTED"}) {
    fields.push_back({std::string("string \"") + s + "\"", string_length_at(good, s), limit});
  }
  each_bad_length_is_refused<hrp::arm_state_t>("ARM_STATE", good, fields, true);
}

hrp::input_health_t input_health() {
  hrp::input_health_t h{};
  h.utime = 1000;
  h.tasks = "camera,estimator";
  h.num_channels = 2;
  h.channel = {"ROBOT_POSE", "ARM_STATE"};
  h.num_reasons = 3;
  h.reason = {"UNDECODABLE", "STALE", "FUTURE"};
  h.accepted = {5, 6};
  h.rejected = {{1, 2, 3}, {4, 5, 6}};
  return h;
}

void test_input_health_lengths(void**) {
  const std::vector<std::uint8_t> good = encode(input_health());
  const auto limit = static_cast<std::int32_t>(fsw_app::kMaxWireStringBytes + 1);
  const std::size_t tasks = string_length_at(good, "camera,estimator");
  const std::size_t first_reason = string_length_at(good, "UNDECODABLE");
  std::vector<LengthField> fields = {
      {"string tasks", tasks, limit},
      {"num_channels", tasks + 4 + std::strlen("camera,estimator") + 1, fsw_app::kMaxWireChannels},
      {"num_reasons", first_reason - 4, hrp::input_health_t::MAX_REASONS}};
  assert_int_equal(read_be32(good, fields[1].at), 2);
  assert_int_equal(read_be32(good, fields[2].at), 3);
  for (const char* s : {"ROBOT_POSE", "ARM_STATE", "UNDECODABLE", "STALE", "FUTURE"}) {
    fields.push_back({std::string("string \"") + s + "\"", string_length_at(good, s), limit});
  }
  // A count of 0 is a good count for an array, but not for these bytes:
  // what follows is then read as something else, which the walker finds.
  each_bad_length_is_refused<hrp::input_health_t>("INPUT_HEALTH", good, fields, false);
}

// DEPTH_FRAME's receiver has its own checked decoder (depth_frame_msg.hpp):
// the point count set to each bad value is refused there, and by the walker.
void test_depth_frame_point_count(void**) {
  hrp::depth_frame_t f{};
  f.width = 4;
  f.height = 2;
  f.num_points = 8;
  for (auto* v : {&f.x_m, &f.y_m, &f.z_m, &f.noise_m}) v->assign(8, 1.0f);
  f.gray_value.assign(8, 7);
  f.confidence.assign(8, 255);
  const std::vector<std::uint8_t> good = encode(f);
  const std::size_t at = 8 + 3 * 8 + 2 * 4;
  assert_int_equal(read_be32(good, at), 8);
  hrp::depth_frame_t out;
  fsw_app::reserve_points(&out, 8);
  assert_true(fsw_app::decode_depth_frame(good.data(), good.size(), 8, &out) ==
              fsw_app::FrameMsgStatus::kOk);
  for (const auto& [value, what] :
       bad_values({"num_points", at, fsw_app::kMaxWireDepthPoints}, good.size())) {
    std::vector<std::uint8_t> bytes = good;
    write_be32(&bytes, at, value);
    const fsw_app::FrameMsgStatus st =
        fsw_app::decode_depth_frame(bytes.data(), bytes.size(), 8, &out);
    const fsw_app::WireFault wf = fsw_app::wire_check(
        static_cast<const hrp::depth_frame_t*>(nullptr), bytes.data(), bytes.size());
    std::printf("  DEPTH_FRAME num_points = %d (%s): %s, walker %s\n", value, what.c_str(),
                fsw_app::to_string(st), fsw_app::to_string(wf));
    assert_true(st != fsw_app::FrameMsgStatus::kOk);
    if (value != 0) assert_true(wf != fsw_app::WireFault::kNone);
  }
}

// The limits are the receivers' reserves: a string of exactly the limit is
// taken without the string growing, one byte more is refused; a string
// whose last byte is not its terminator is refused.
void test_string_limit_and_terminator(void**) {
  hrp::arm_state_t a = arm_state();
  a.fault_text.assign(fsw_app::kMaxWireStringBytes, 'x');
  std::vector<std::uint8_t> bytes = encode(a);
  fsw_app::Mailbox<hrp::arm_state_t> box;
  box.deliver(bytes.data(), static_cast<std::uint32_t>(bytes.size()), fsw_app::kNoReceiverClock);
  assert_int_equal(box.input_counts().accepted.load(), 1);

  a.fault_text.push_back('x');
  bytes = encode(a);
  assert_true(fsw_app::wire_check(&a, bytes.data(), bytes.size()) ==
              fsw_app::WireFault::kBadStringLength);

  a = arm_state();
  bytes = encode(a);
  const std::size_t at = string_length_at(bytes, "NONE");
  bytes[at + 4 + 4] = 'E';  // the terminator overwritten
  assert_true(fsw_app::wire_check(&a, bytes.data(), bytes.size()) ==
              fsw_app::WireFault::kUnterminated);
  // A NUL inside (found by the fuzzer): the held string would not be the
  // one re-sent.
  bytes = encode(a);
  bytes[at + 4 + 1] = 0;
  assert_true(fsw_app::wire_check(&a, bytes.data(), bytes.size()) ==
              fsw_app::WireFault::kUnterminated);
}

// A utime near INT64_MIN after a held message overflowed the age test (the
// fuzzer's find): every type's utime must be non-negative.
void test_negative_utime_is_refused(void**) {
  fsw_app::Mailbox<hrp::arm_state_t> box;
  hrp::arm_state_t a = arm_state();
  std::vector<std::uint8_t> bytes = encode(a);
  box.deliver(bytes.data(), static_cast<std::uint32_t>(bytes.size()), fsw_app::kNoReceiverClock);
  a.utime = INT64_MIN + 5;
  bytes = encode(a);
  box.deliver(bytes.data(), static_cast<std::uint32_t>(bytes.size()), fsw_app::kNoReceiverClock);
  assert_int_equal(box.input_counts().rejected[static_cast<int>(InputReject::kOutOfRange)].load(),
                   1);
  assert_int_equal(box.input_counts().accepted.load(), 1);
}

// Whatever a receiver throws ends at the hub, counted; the next message is
// delivered as usual.
struct ThrowingReceiver {
  int calls = 0;
  void deliver(const void*, std::uint32_t, std::int64_t) {
    if (++calls == 1) throw std::length_error("basic_string::_M_replace");
  }
};

void test_hub_contains_what_a_receiver_throws(void**) {
  fsw_app::LcmHub hub("memq://");
  ThrowingReceiver r;
  hub.subscribe("ANY", &r);
  const std::uint8_t b[] = {1, 2, 3};
  hub.publish_raw("ANY", b, sizeof b);
  hub.publish_raw("ANY", b, sizeof b);
  assert_true(hub.handle(100) > 0);
  assert_true(hub.handle(100) > 0);
  assert_int_equal(r.calls, 2);
  assert_int_equal(hub.receiver_faults(), 1);
}

// The walker agrees with the generated encoder on every layout: real
// messages with strings of many lengths pass, whole.
void test_walker_accepts_what_the_encoder_writes(void**) {
  for (std::size_t n : {0, 1, 7, 31, 160}) {
    hrp::arm_state_t a = arm_state();
    a.state_name.assign(n, 's');
    a.fault_text.assign(160 - n, 't');
    std::vector<std::uint8_t> b = encode(a);
    assert_true(fsw_app::wire_check(&a, b.data(), b.size()) == fsw_app::WireFault::kNone);
    hrp::input_health_t h = input_health();
    h.channel[1].assign(n, 'c');
    b = encode(h);
    assert_true(fsw_app::wire_check(&h, b.data(), b.size()) == fsw_app::WireFault::kNone);
    b.resize(b.size() - 1);
    assert_true(fsw_app::wire_check(&h, b.data(), b.size()) == fsw_app::WireFault::kTruncated);
  }
}

}  // namespace

int main() {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_arm_state_lengths),
      cmocka_unit_test(test_input_health_lengths),
      cmocka_unit_test(test_depth_frame_point_count),
      cmocka_unit_test(test_string_limit_and_terminator),
      cmocka_unit_test(test_negative_utime_is_refused),
      cmocka_unit_test(test_hub_contains_what_a_receiver_throws),
      cmocka_unit_test(test_walker_accepts_what_the_encoder_writes),
  };
  return cmocka_run_group_tests(tests, nullptr, nullptr);
}
