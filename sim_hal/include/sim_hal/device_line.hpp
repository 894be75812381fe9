#pragma once
// The simulated device's end of a serial line (a pty master): the faults
// injected into its replies, and the replies held back until their time
// (a servo's return delay, an injected lateness) so that a late reply never
// holds up the device's thread. Shared by the simulated servos and the
// simulated gripper board.
#include <cstddef>
#include <cstdint>

#include "sim_hal/sim_random.hpp"

namespace sim_hal {

struct BusFaults {
  double drop_byte_probability = 0.0;  // each reply byte, independently
  double corrupt_checksum_probability = 0.0;
  std::uint32_t late_reply_us = 0;  // added to every reply
  bool no_reply = false;            // the device stays silent
  bool echo = false;                // the adapter hears what is sent (half duplex)
};

class DeviceLine {
 public:
  static constexpr std::size_t kMaxReply = 72;  // a Dynamixel packet's largest
  static constexpr std::size_t kMaxPending = 16;

  explicit DeviceLine(std::uint64_t seed) : rng_(seed) {}
  void attach(int fd) { fd_ = fd; }

  // Writes the bytes now (the echo of a half-duplex adapter).
  void send_now(const std::uint8_t* bytes, std::size_t n) const;
  // A reply, due at due_us plus the injected lateness: corrupted (its last
  // byte, the checksum, flipped) and thinned out as the faults say, or not
  // sent at all. A full queue drops it, as a jammed line would.
  void reply(const std::uint8_t* bytes, std::size_t n, std::int64_t due_us,
             const BusFaults& faults);
  // Sends every queued reply that is due, earliest first.
  void send_due(std::int64_t now_us);
  // The earliest due time queued; INT64_MAX when none.
  std::int64_t next_due_us() const;

 private:
  struct Pending {
    std::int64_t due_us = 0;
    std::size_t n = 0;
    std::uint8_t bytes[kMaxReply] = {};
  };
  int fd_ = -1;
  SimRandom rng_;
  Pending pending_[kMaxPending];
  std::size_t n_pending_ = 0;
};

}  // namespace sim_hal
