// libFuzzer: both ends of the gripper protocol on arbitrary bytes: the
// host's reply parser (for each command it may await) and the board
// firmware's command parser with its control step. Neither may touch
// memory out of bounds; the firmware's reply must always be a whole,
// CRC-correct packet that the host's parser accepts.
#include <cstddef>
#include <cstdint>
#include <cstdlib>

#include "gripper/gripper_board.hpp"
#include "gripper_fw.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  gripper::ReplyParser host;
  host.expect(static_cast<std::uint8_t>(0x81 + data[0] % 10));
  for (std::size_t k = 1; k < size; ++k) host.push(data[k]);

  gfw_state board;
  gfw_init(&board, 0);
  std::uint32_t now = 0;
  for (std::size_t k = 1; k < size; ++k) {
    board.tx_len = 0;
    gfw_receive(&board, data[k], static_cast<std::uint8_t>(data[k - 1] & 3), now);
    if (board.tx_len > 0) {
      if (board.tx_len > GFW_MAX_REPLY) std::abort();
      gripper::ReplyParser check;
      check.expect(board.tx[0]);
      gripper::ReplyParser::Event last = gripper::ReplyParser::Event::kNone;
      for (std::uint8_t j = 0; j < board.tx_len; ++j) last = check.push(board.tx[j]);
      if (last != gripper::ReplyParser::Event::kReply) std::abort();
    }
    now += data[k] % 7;
    gfw_tick(&board, static_cast<std::int32_t>(data[k]) * 13 - 1000,
             static_cast<std::uint16_t>(data[k] * 11), now);
    if (board.pwm > 255 || board.pwm < -255) std::abort();
  }
  return 0;
}
