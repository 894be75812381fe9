#pragma once
// Dynamixel Protocol 1.0 over a serial port: one instruction out, at most
// one status packet back, with timeouts worked out from the baud rate and
// the servos' return delay, and a bounded number of retries. No allocation
// and no exceptions: every call returns a status and the servo's error bits.
//
// Protocol 1.0 status packets carry no transaction number, so a reply that
// comes after its timeout looks like the answer to the next instruction
// (the maker's SDK takes it so). The bus keeps them apart three ways:
//  - a reply counts only with the ID asked and the parameter count the
//    instruction implies (a READ of N bytes: N parameters; others: none);
//  - before each instruction goes out, whatever has arrived is read,
//    parsed and discarded (counted as stale_replies);
//  - after a transaction in which an attempt timed out, the next
//    instruction is held back until twice that attempt's reply timeout has
//    passed since it was sent, so that its late reply lands in the discard
//    and not in the next transaction's window. A reply later than that is
//    indistinguishable from a real one on this protocol.
#include <cstddef>
#include <cstdint>

#include "dynamixel/protocol1.hpp"
#include "hal/clock.hpp"
#include "hal/serial_port.hpp"

namespace dynamixel {

enum class BusStatus : std::uint8_t {
  kOk,               // a valid reply (which may still carry servo error bits)
  kTimeout,          // no reply in time, after every retry
  kBadChecksum,      // only corrupt replies, after every retry
  kWrongReply,       // only replies from another ID or of the wrong length; a servo's
                     // refusal of a READ (no data, its error bits in servo_error) too
  kSerialError,      // the port failed (see serial_status)
  kInvalidArgument,  // an ID, address or length that cannot be sent
};
const char* to_string(BusStatus status);

struct BusResult {
  BusStatus status = BusStatus::kOk;
  std::uint8_t servo_error = 0;  // the status packet's ErrorBit flags
  hal::SerialStatus serial_status = hal::SerialStatus::kOk;
  bool ok() const { return status == BusStatus::kOk && servo_error == 0; }
};

struct BusConfig {
  std::uint32_t return_delay_us = 0;  // the servos' return delay time (register 5)
  std::uint32_t margin_us = 3000;     // on top of the bytes' time: USB and scheduling latency
  std::uint8_t retries = 2;           // extra attempts after a timeout or a corrupt reply
  // The servos' status return level (register 16): 2 answers everything,
  // 1 only PING and READ, 0 only PING.
  std::uint8_t status_return_level = 2;
};

struct BusCounters {
  std::uint32_t transactions = 0, retries = 0, timeouts = 0, bad_checksums = 0, wrong_replies = 0,
                bad_lengths = 0;
  // Whole status packets found on the line before an instruction was sent
  // (late replies to earlier ones), discarded.
  std::uint32_t stale_replies = 0;
  // Replies whose checksum-error bit said the servo received a damaged
  // instruction (and so did nothing): retried like a lost reply.
  std::uint32_t instruction_checksum_errors = 0;
};

class Bus {
 public:
  // Neither the port nor the clock is owned; both must outlive the bus.
  Bus(hal::SerialPort& port, const hal::Clock& clock, const BusConfig& config = BusConfig{});

  BusResult ping(std::uint8_t id);
  BusResult read(std::uint8_t id, std::uint8_t address, std::uint8_t length, std::uint8_t* out);
  BusResult write(std::uint8_t id, std::uint8_t address, const std::uint8_t* data,
                  std::uint8_t length);
  // Staged write, carried out by action() (several servos moving at once).
  BusResult reg_write(std::uint8_t id, std::uint8_t address, const std::uint8_t* data,
                      std::uint8_t length);
  BusResult action(std::uint8_t id = kBroadcastId);
  // One packet writing `length` bytes at `address` on each of n servos;
  // data holds n * length bytes in the order of ids. Never answered.
  BusResult sync_write(std::uint8_t address, std::uint8_t length, const std::uint8_t* ids,
                       const std::uint8_t* data, std::size_t n);

  BusResult read_u8(std::uint8_t id, std::uint8_t address, std::uint8_t* value);
  BusResult read_u16(std::uint8_t id, std::uint8_t address, std::uint16_t* value);
  BusResult write_u8(std::uint8_t id, std::uint8_t address, std::uint8_t value);
  BusResult write_u16(std::uint8_t id, std::uint8_t address, std::uint16_t value);

  // The time allowed for a reply of `reply_bytes` after sending
  // `sent_bytes`: their time on the wire at the port's rate (10 bits a
  // byte), the return delay and the margin.
  std::int64_t reply_timeout_us(std::size_t sent_bytes, std::size_t reply_bytes) const;

  const BusConfig& config() const { return config_; }
  void set_config(const BusConfig& config) { config_ = config; }
  const BusCounters& counters() const { return counters_; }
  hal::SerialPort& port() { return port_; }

 private:
  // Sends the instruction and, when one is due, waits for the reply of
  // `expect_params` parameters from `id`.
  BusResult transact(std::uint8_t id, Instruction instruction, const std::uint8_t* params,
                     std::size_t n_params, bool expect_reply, std::size_t expect_params,
                     StatusPacket* reply);
  // WRITE and REG_WRITE: the address, then the data.
  BusResult write_at(Instruction instruction, std::uint8_t id, std::uint8_t address,
                     const std::uint8_t* data, std::uint8_t length);
  // *unanswered: nothing came that could be this attempt's reply (its
  // reply may still be on its way).
  BusResult wait_reply(std::uint8_t id, std::size_t expect_params, std::int64_t deadline_us,
                       StatusPacket* reply, bool* unanswered);
  bool replies_to(Instruction instruction, std::uint8_t id) const;
  // Reads and discards until the deadline.
  void drain_until(std::int64_t deadline_us);
  // Before an instruction: waits out the quiet time a timeout left, then
  // reads what has arrived; whole packets in it count as stale replies.
  void discard_stale();
  void count_stale(const std::uint8_t* bytes, std::size_t n);

  hal::SerialPort& port_;
  const hal::Clock& clock_;
  BusConfig config_;
  BusCounters counters_;
  StatusParser parser_;
  StatusParser stale_parser_;  // kept apart so a stale fragment cannot start a reply
  // No instruction goes out before this time (after a timeout; see above).
  std::int64_t quiet_until_us_ = 0;
  std::uint8_t tx_[kMaxPacket];
  std::uint8_t params_[kMaxParams];
};

}  // namespace dynamixel
