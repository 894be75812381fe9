#pragma once
// Dynamixel Protocol 1.0 over a serial port: one instruction out, at most
// one status packet back, with timeouts worked out from the baud rate and
// the servos' return delay, and a bounded number of retries. No allocation
// and no exceptions: every call returns a status and the servo's error bits.
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
  kWrongReply,       // a reply from another ID, or of the wrong length
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
  BusResult wait_reply(std::uint8_t id, std::size_t expect_params, std::int64_t deadline_us,
                       StatusPacket* reply);
  bool replies_to(Instruction instruction, std::uint8_t id) const;
  // Reads and discards until the deadline.
  void drain_until(std::int64_t deadline_us);

  hal::SerialPort& port_;
  const hal::Clock& clock_;
  BusConfig config_;
  BusCounters counters_;
  StatusParser parser_;
  std::uint8_t tx_[kMaxPacket];
  std::uint8_t params_[kMaxParams];
};

}  // namespace dynamixel
