#include "sim_hal/sim_servo_bus.hpp"

// The kernel's termios2 (the rate as a number, as our driver sets it with
// BOTHER); glibc's <termios.h> cannot be included beside it.
#include <asm/termbits.h>
#include <poll.h>
#include <sys/ioctl.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstring>

#include "dynamixel/protocol1.hpp"

namespace sim_hal {

SimServoBus::SimServoBus(std::vector<std::uint8_t> ids, std::uint64_t seed) : line_(seed) {
  for (std::uint8_t id : ids) servos_.emplace_back(id);
  torques_.assign(servos_.size(), 0.0);
}

SimServoBus::~SimServoBus() {
  stop();
}

bool SimServoBus::start(std::string* error) {
  if (!pty_.open(error)) return false;
  line_.attach(pty_.master_fd());
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

void SimServoBus::set_position(std::uint8_t id, double angle_rad) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (SimServo* s = find(id)) s->set_position_rad(angle_rad);
}

void SimServoBus::power_cycle(std::uint8_t id) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (SimServo* s = find(id)) s->power_cycle();
}

std::uint32_t SimServoBus::line_baud() const {
  // On the master, the terminal ioctls read the slave's settings (Linux
  // hands them to the linked tty), so this is the rate the client chose.
  struct termios2 tio;
  if (pty_.master_fd() < 0 || ioctl(pty_.master_fd(), TCGETS2, &tio) != 0) return 0;
  return tio.c_ospeed;
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

void SimServoBus::run() {
  dynamixel::InstructionParser parser;
  std::uint8_t rx[256];
  std::int64_t last_us = clock_.now_us();
  while (running_) {
    // Wake for input, for the next reply due, or every millisecond for the
    // motion model.
    const std::int64_t wait_us =
        std::clamp<std::int64_t>(line_.next_due_us() - clock_.now_us(), 0, 1000);
    struct pollfd p = {pty_.master_fd(), POLLIN, 0};
    struct timespec ts = {0, static_cast<long>(wait_us * 1000)};
    ppoll(&p, 1, &ts, nullptr);
    const std::int64_t now = clock_.now_us();
    line_.send_due(now);
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
    if (faults.echo) line_.send_now(rx, static_cast<std::size_t>(n));
    // The rate these bytes came at: read once per read(), as a client
    // changes it only between packets. Unknown (0) is heard by all.
    const std::uint32_t host_bps = line_baud();
    for (ssize_t k = 0; k < n; ++k) {
      const dynamixel::ParseEvent event = parser.push(rx[k]);
      if (event != dynamixel::ParseEvent::kPacket && event != dynamixel::ParseEvent::kBadChecksum) {
        continue;
      }
      ++packets_;
      const dynamixel::InstructionPacket packet = parser.packet();
      std::uint8_t out[dynamixel::kMaxPacket];
      std::size_t out_n = 0;
      std::uint32_t delay_us = 0;
      {
        std::lock_guard<std::mutex> lock(mutex_);
        for (SimServo& s : servos_) {
          if (packet.id != s.id() && packet.id != dynamixel::kBroadcastId) continue;
          // At another rate the servo's UART sees only garbage. The check
          // comes before the packet is handled, so a change of the Baud
          // Rate applies from the packet after the one that wrote it (whose
          // reply still goes out).
          if (host_bps != 0 && !s.understands_baud(host_bps)) continue;
          std::uint8_t error = 0, params[dynamixel::kMaxParams];
          std::size_t n_params = 0;
          const bool due = event == dynamixel::ParseEvent::kPacket
                               ? s.handle(packet, &error, params, &n_params)
                               : s.handle_bad_checksum(packet, &error);
          if (due) {
            out_n = dynamixel::encode_status(s.id(), error, params, n_params, out);
            delay_us = s.return_delay_us();
          }
        }
      }
      line_.reply(out, out_n, clock_.now_us() + delay_us, faults);
    }
  }
}

}  // namespace sim_hal
