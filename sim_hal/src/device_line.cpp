#include "sim_hal/device_line.hpp"

#include <unistd.h>

#include <cstring>
#include <limits>

namespace sim_hal {

void DeviceLine::send_now(const std::uint8_t* bytes, std::size_t n) const {
  std::size_t sent = 0;
  for (int tries = 0; sent < n && tries < 100; ++tries) {
    const ssize_t w = ::write(fd_, bytes + sent, n - sent);
    if (w > 0) sent += static_cast<std::size_t>(w);
  }
}

void DeviceLine::reply(const std::uint8_t* bytes, std::size_t n, std::int64_t due_us,
                       const BusFaults& faults) {
  if (faults.no_reply || n == 0 || n > kMaxReply || n_pending_ == kMaxPending) return;
  Pending& p = pending_[n_pending_++];
  p.due_us = due_us + faults.late_reply_us;
  std::memcpy(p.bytes, bytes, n);
  // 0x15 keeps a 7-bit byte 7-bit (the gripper's CRC) and changes any byte.
  if (rng_.uniform() < faults.corrupt_checksum_probability) p.bytes[n - 1] ^= 0x15;
  p.n = 0;
  for (std::size_t b = 0; b < n; ++b) {
    if (rng_.uniform() >= faults.drop_byte_probability) p.bytes[p.n++] = p.bytes[b];
  }
}

void DeviceLine::send_due(std::int64_t now_us) {
  for (std::size_t pass = 0; pass < kMaxPending && n_pending_ > 0; ++pass) {
    std::size_t first = 0;
    for (std::size_t k = 1; k < n_pending_; ++k)
      if (pending_[k].due_us < pending_[first].due_us) first = k;
    if (pending_[first].due_us > now_us) return;
    send_now(pending_[first].bytes, pending_[first].n);
    pending_[first] = pending_[--n_pending_];
  }
}

std::int64_t DeviceLine::next_due_us() const {
  std::int64_t due = std::numeric_limits<std::int64_t>::max();
  for (std::size_t k = 0; k < n_pending_; ++k)
    due = pending_[k].due_us < due ? pending_[k].due_us : due;
  return due;
}

}  // namespace sim_hal
