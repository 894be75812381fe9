// The Dynamixel 1.0 codec against the maker's test vectors, and the status
// parser's resynchronisation.
#include <cstring>

#include "cmocka_cpp.hpp"
#include "dynamixel/protocol1.hpp"

using namespace dynamixel;

namespace {

void test_maker_vectors_encode(void**) {
  std::uint8_t out[kMaxPacket];
  const std::uint8_t goal[] = {0x0C, 0x64, 0xAA};  // write goal position
  const std::uint8_t want_goal[] = {0xFF, 0xFF, 0x01, 0x05, 0x03, 0x0C, 0x64, 0xAA, 0xDC};
  assert_int_equal(encode_instruction(1, Instruction::kWrite, goal, 3, out), sizeof want_goal);
  assert_memory_equal(out, want_goal, sizeof want_goal);
  const std::uint8_t want_ping[] = {0xFF, 0xFF, 0x01, 0x02, 0x01, 0xFB};
  assert_int_equal(encode_instruction(1, Instruction::kPing, nullptr, 0, out), sizeof want_ping);
  assert_memory_equal(out, want_ping, sizeof want_ping);
  const std::uint8_t temp[] = {0x2B, 0x01};
  const std::uint8_t want_read[] = {0xFF, 0xFF, 0x01, 0x04, 0x02, 0x2B, 0x01, 0xCC};
  assert_int_equal(encode_instruction(1, Instruction::kRead, temp, 2, out), sizeof want_read);
  assert_memory_equal(out, want_read, sizeof want_read);
  std::uint8_t too_many[kMaxParams + 1] = {};
  assert_int_equal(encode_instruction(1, Instruction::kWrite, too_many, sizeof too_many, out), 0);
}

ParseEvent feed(StatusParser& p, const std::uint8_t* bytes, std::size_t n, int* packets) {
  ParseEvent last = ParseEvent::kNone;
  for (std::size_t k = 0; k < n; ++k) {
    const ParseEvent e = p.push(bytes[k]);
    if (e == ParseEvent::kPacket) ++*packets;
    if (e != ParseEvent::kNone) last = e;
  }
  return last;
}

void test_maker_vectors_parse(void**) {
  StatusParser p;
  int packets = 0;
  const std::uint8_t ping_reply[] = {0xFF, 0xFF, 0x01, 0x02, 0x00, 0xFC};
  assert_int_equal(static_cast<int>(feed(p, ping_reply, sizeof ping_reply, &packets)),
                   static_cast<int>(ParseEvent::kPacket));
  assert_int_equal(p.packet().id, 1);
  assert_int_equal(p.packet().n_params, 0);
  const std::uint8_t temp_reply[] = {0xFF, 0xFF, 0x01, 0x03, 0x00, 0x20, 0xDB};
  feed(p, temp_reply, sizeof temp_reply, &packets);
  assert_int_equal(packets, 2);
  assert_int_equal(p.packet().params[0], 32);  // 32 degC
}

void test_parser_resynchronises(void**) {
  StatusParser p;
  int packets = 0;
  // Noise, a corrupt packet, an impossible length, then a good packet.
  const std::uint8_t stream[] = {0x12, 0xFF, 0x00, 0xFF, 0xFF, 0x01, 0x03, 0x00, 0x20, 0xDA, 0xFF,
                                 0xFF, 0x01, 0xF0, 0xFF, 0xFF, 0xFF, 0x01, 0x02, 0x24, 0xD8};
  int bad_checksum = 0, bad_length = 0;
  for (std::uint8_t b : stream) {
    const ParseEvent e = p.push(b);
    packets += e == ParseEvent::kPacket;
    bad_checksum += e == ParseEvent::kBadChecksum;
    bad_length += e == ParseEvent::kBadLength;
  }
  assert_int_equal(bad_checksum, 1);
  assert_int_equal(bad_length, 1);
  assert_int_equal(packets, 1);
  assert_int_equal(p.packet().error, kErrorOverload | kErrorOverheating);
  assert_string_equal(error_bit_name(kErrorOverload), "OVERLOAD");
  assert_string_equal(to_string(ParseEvent::kBadLength), "BAD_LENGTH");
}

}  // namespace

int main() {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_maker_vectors_encode),
      cmocka_unit_test(test_maker_vectors_parse),
      cmocka_unit_test(test_parser_resynchronises),
  };
  return cmocka_run_group_tests(tests, nullptr, nullptr);
}
