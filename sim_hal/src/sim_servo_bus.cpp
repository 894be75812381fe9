#include "sim_hal/sim_servo_bus.hpp"

#include <poll.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstring>

#include "dynamixel/protocol1.hpp"

namespace sim_hal {

SimServoBus::SimServoBus(std::vector<std::uint8_t> ids, std::uint64_t seed) : rng_state_(seed) {
  for (std::uint8_t id : ids) servos_.emplace_back(id);
  torques_.assign(servos_.size(), 0.0);
}

SimServoBus::~SimServoBus() {
  stop();
}

bool SimServoBus::start(std::string* error) {
  if (!pty_.open(error)) return false;
  running_ = true;
  thread_ = std::thread([this] { run(); });
  return true;
}

void SimServoBus::stop() {
  running_ = false;
  if (thread_.joinable()) thread_.join();
  pty_.close();
}

void SimServoBus::set_faults(const BusFaults& faults) {
  std::lock_guard<std::mutex> lock(mutex_);
  faults_ = faults;
}

BusFaults SimServoBus::faults() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return faults_;
}

SimServo* SimServoBus::find(std::uint8_t id) {
  for (SimServo& s : servos_)
    if (s.id() == id) return &s;
  return nullptr;
}

void SimServoBus::force_error_bits(std::uint8_t id, std::uint8_t bits) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (SimServo* s = find(id)) s->force_error_bits(bits);
}

void SimServoBus::set_external_torque(std::uint8_t id, double torque_nm) {
  std::lock_guard<std::mutex> lock(mutex_);
  for (std::size_t k = 0; k < servos_.size(); ++k)
    if (servos_[k].id() == id) torques_[k] = torque_nm;
}

bool SimServoBus::servo(std::uint8_t id, SimServo* out) const {
  std::lock_guard<std::mutex> lock(mutex_);
  for (const SimServo& s : servos_) {
    if (s.id() == id) {
      *out = s;
      return true;
    }
  }
  return false;
}

void SimServoBus::queue_reply(const std::uint8_t* bytes, std::size_t n, std::int64_t due_us) {
  if (n_pending_ == kMaxPending || n > dynamixel::kMaxPacket) return;  // a full bus drops it
  PendingReply& p = pending_[n_pending_++];
  p.due_us = due_us;
  p.n = n;
  std::memcpy(p.bytes, bytes, n);
}

void SimServoBus::send_due_replies(std::int64_t now_us) {
  // In due order: the earliest first.
  for (std::size_t pass = 0; pass < kMaxPending && n_pending_ > 0; ++pass) {
    std::size_t first = 0;
    for (std::size_t k = 1; k < n_pending_; ++k)
      if (pending_[k].due_us < pending_[first].due_us) first = k;
    if (pending_[first].due_us > now_us) return;
    send(pending_[first].bytes, pending_[first].n);
    pending_[first] = pending_[--n_pending_];
  }
}

void SimServoBus::send(const std::uint8_t* bytes, std::size_t n) {
  std::size_t sent = 0;
  for (int tries = 0; sent < n && tries < 100; ++tries) {
    const ssize_t w = ::write(pty_.master_fd(), bytes + sent, n - sent);
    if (w > 0) sent += static_cast<std::size_t>(w);
  }
}

void SimServoBus::run() {
  dynamixel::InstructionParser parser;
  std::uint8_t rx[256];
  std::int64_t last_us = clock_.now_us();
  while (running_) {
    // Wake for input, for the next reply due, or every millisecond for the
    // motion model.
    std::int64_t wait_us = 1000;
    for (std::size_t k = 0; k < n_pending_; ++k) {
      wait_us = std::min(wait_us, std::max<std::int64_t>(0, pending_[k].due_us - clock_.now_us()));
    }
    struct pollfd p = {pty_.master_fd(), POLLIN, 0};
    struct timespec ts = {0, static_cast<long>(wait_us * 1000)};
    ppoll(&p, 1, &ts, nullptr);
    const std::int64_t now = clock_.now_us();
    send_due_replies(now);
    {
      std::lock_guard<std::mutex> lock(mutex_);
      for (std::size_t k = 0; k < servos_.size(); ++k) {
        servos_[k].step(1e-6 * static_cast<double>(now - last_us), torques_[k]);
      }
    }
    last_us = now;
    if (!(p.revents & POLLIN)) continue;
    const ssize_t n = ::read(pty_.master_fd(), rx, sizeof(rx));
    if (n <= 0) continue;
    BusFaults faults = this->faults();
    if (faults.echo) send(rx, static_cast<std::size_t>(n));
    for (ssize_t k = 0; k < n; ++k) {
      if (parser.push(rx[k]) != dynamixel::ParseEvent::kPacket) continue;
      ++packets_;
      const dynamixel::InstructionPacket packet = parser.packet();
      std::uint8_t out[dynamixel::kMaxPacket];
      std::size_t out_n = 0;
      std::uint32_t delay_us = 0;
      {
        std::lock_guard<std::mutex> lock(mutex_);
        for (SimServo& s : servos_) {
          if (packet.id != s.id() && packet.id != dynamixel::kBroadcastId) continue;
          std::uint8_t error = 0, params[dynamixel::kMaxParams];
          std::size_t n_params = 0;
          if (s.handle(packet, &error, params, &n_params)) {
            out_n = dynamixel::encode_status(s.id(), error, params, n_params, out);
            delay_us = s.return_delay_us();
          }
        }
      }
      if (out_n == 0 || faults.no_reply) continue;
      auto uniform = [this] {
        std::uint64_t z = (rng_state_ += 0x9e3779b97f4a7c15ull);
        z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
        z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
        return static_cast<double>((z ^ (z >> 31)) >> 11) * 0x1.0p-53;
      };
      if (uniform() < faults.corrupt_checksum_probability) out[out_n - 1] ^= 0x5A;
      std::uint8_t kept[dynamixel::kMaxPacket];
      std::size_t kept_n = 0;
      for (std::size_t b = 0; b < out_n; ++b) {
        if (uniform() >= faults.drop_byte_probability) kept[kept_n++] = out[b];
      }
      queue_reply(kept, kept_n, clock_.now_us() + delay_us + faults.late_reply_us);
    }
  }
}

}  // namespace sim_hal
