#include "sim_hal/sim_gripper.hpp"

#include <poll.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>

namespace sim_hal {

SimGripperBoard::SimGripperBoard(const GripperModel& model) : model_(model) {}

SimGripperBoard::~SimGripperBoard() {
  stop();
}

bool SimGripperBoard::start(std::string* error) {
  if (!pty_.open(error)) return false;
  line_.attach(pty_.master_fd());
  {
    std::lock_guard<std::mutex> lock(mutex_);
    gfw_init(&fw_, static_cast<std::uint32_t>(clock_.now_us() / 1000));
  }
  running_ = true;
  thread_ = std::thread([this] { run(); });
  return true;
}

void SimGripperBoard::stop() {
  running_ = false;
  if (thread_.joinable()) thread_.join();
  pty_.close();
}

void SimGripperBoard::set_handrail_raw(int raw) {
  std::lock_guard<std::mutex> lock(mutex_);
  handrail_raw_ = raw;
}

void SimGripperBoard::set_winding_short(bool shorted) {
  std::lock_guard<std::mutex> lock(mutex_);
  winding_short_ = shorted;
}

void SimGripperBoard::set_faults(const BusFaults& faults) {
  std::lock_guard<std::mutex> lock(mutex_);
  faults_ = faults;
}

GripperSnapshot SimGripperBoard::snapshot() const {
  std::lock_guard<std::mutex> lock(mutex_);
  GripperSnapshot s;
  s.position_raw = position_;
  s.velocity_counts_s = velocity_;
  s.current_a = current_a_;
  s.pwm = fw_.pwm;
  s.calibrated = fw_.calibrated != 0;
  s.safe_start = fw_.safe_start != 0;
  return s;
}

// A DC gearmotor: the speed follows the applied voltage with a first-order
// lag; the current is what the voltage left after back-EMF drives through
// the winding. A stop (hard stop or handrail) holds the speed at zero.
void SimGripperBoard::step_motor(double dt_s, int pwm) {
  const double volts = model_.supply_v * pwm / 255.0;
  const double ke = model_.supply_v / model_.free_speed_counts_s;
  const double target = volts / ke;
  velocity_ += (target - velocity_) * std::min(1.0, dt_s / model_.time_constant_s);
  double next = position_ + velocity_ * dt_s;
  double upper = model_.closed_stop_raw;
  if (handrail_raw_ >= 0) upper = std::min<double>(upper, handrail_raw_);
  if (next >= upper) {
    next = upper;
    velocity_ = std::min(velocity_, 0.0);
  }
  if (next <= model_.open_stop_raw) {
    next = model_.open_stop_raw;
    velocity_ = std::max(velocity_, 0.0);
  }
  position_ = next;
  const double ohm = winding_short_ ? model_.winding_ohm / 4.0 : model_.winding_ohm;
  current_a_ = std::fabs(volts - (winding_short_ ? 0.0 : ke * velocity_)) / ohm;
}

void SimGripperBoard::run() {
  std::uint8_t rx[64];
  std::int64_t last_us = clock_.now_us();
  while (running_) {
    struct pollfd p = {pty_.master_fd(), POLLIN, 0};
    poll(&p, 1, 1);
    const std::int64_t now_us = clock_.now_us();
    const std::uint32_t now_ms = static_cast<std::uint32_t>(now_us / 1000);
    line_.send_due(now_us);
    BusFaults faults;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      faults = faults_;
    }
    // Bytes first, then the tick: on the board the UART interrupt takes a
    // byte the moment it lands, so a command waiting in the pty after this
    // thread was descheduled arrived before the tick that catches up, and
    // must count against the serial timeout as such.
    const ssize_t n = (p.revents & POLLIN) ? ::read(pty_.master_fd(), rx, sizeof(rx)) : 0;
    if (n > 0 && faults.echo) line_.send_now(rx, static_cast<std::size_t>(n));
    for (ssize_t k = 0; k < n; ++k) {
      std::uint8_t out[GFW_MAX_REPLY];
      std::size_t out_n = 0;
      {
        std::lock_guard<std::mutex> lock(mutex_);
        fw_.tx_len = 0;
        gfw_receive(&fw_, rx[k], 0, now_ms);
        out_n = fw_.tx_len;
        std::copy(fw_.tx, fw_.tx + out_n, out);
        fw_.tx_len = 0;
      }
      line_.reply(out, out_n, now_us, faults);
    }
    line_.send_due(now_us);  // a reply not held back goes out at once
    {
      std::lock_guard<std::mutex> lock(mutex_);
      // The firmware's 1 kHz tick, caught up in whole milliseconds.
      const std::int64_t steps = std::min<std::int64_t>((now_us - last_us) / 1000, 50);
      for (std::int64_t k = 0; k < steps; ++k) {
        step_motor(1e-3, fw_.pwm);
        const std::uint16_t ma = static_cast<std::uint16_t>(std::lround(current_a_ * 1000.0));
        gfw_tick(&fw_, static_cast<std::int32_t>(std::lround(position_)), ma,
                 now_ms - static_cast<std::uint32_t>(steps - 1 - k));
      }
      if (steps > 0) last_us += steps * 1000;
      if (now_us - last_us > 50000) last_us = now_us;  // after a long stall
    }
  }
}

}  // namespace sim_hal
