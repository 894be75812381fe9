#pragma once
// Simulated AX-12A servos on one pseudo-terminal, as on a half-duplex
// Dynamixel bus: a thread reads instruction packets from the pty, lets the
// addressed servo answer after its return delay, and moves the servos in
// real time. Faults can be switched on and off while it runs.
//
// A pty carries no signal, but it keeps the rate its client set (termios;
// read back on the master). A servo hears a packet only when that rate is
// within 3 % of its own Baud Rate (4), as a UART would; at any other rate
// it stays silent, so a scan finds each servo at its own rate only.
#include <atomic>
#include <cstdint>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "hal/clock.hpp"
#include "sim_hal/device_line.hpp"
#include "sim_hal/pty.hpp"
#include "sim_hal/sim_servo.hpp"

namespace sim_hal {

class SimServoBus {
 public:
  // Servos with these IDs (the perching arm's are 1 and 2).
  explicit SimServoBus(std::vector<std::uint8_t> ids = {1, 2}, std::uint64_t seed = 1);
  ~SimServoBus();

  bool start(std::string* error);  // opens the pty and starts the thread
  void stop();
  const std::string& path() const { return pty_.slave_path(); }

  void set_faults(const BusFaults& faults);
  BusFaults faults() const;
  // Forces servo error bits (overload, overheating) on one servo.
  void force_error_bits(std::uint8_t id, std::uint8_t bits);
  // An external torque on a servo's output (N m), e.g. a load on the arm.
  void set_external_torque(std::uint8_t id, double torque_nm);
  // Places a servo's shaft (and goal) at an angle, e.g. the arm stowed.
  void set_position(std::uint8_t id, double angle_rad);
  // Switches a servo off and on (SimServo::power_cycle): the only way to
  // clear its Lock.
  void power_cycle(std::uint8_t id);
  // The rate the pty's client has set (its output speed), 0 when unknown.
  std::uint32_t line_baud() const;
  // A copy of a servo's state, for tests and monitors.
  bool servo(std::uint8_t id, SimServo* out) const;
  std::uint64_t packets_handled() const { return packets_.load(); }

 private:
  void run();
  SimServo* find(std::uint8_t id);

  PtyDevice pty_;
  hal::MonotonicClock clock_;
  std::thread thread_;
  std::atomic<bool> running_{false};
  std::atomic<std::uint64_t> packets_{0};
  mutable std::mutex mutex_;  // guards servos_, torques_, faults_
  std::vector<SimServo> servos_;
  std::vector<double> torques_;
  BusFaults faults_;
  DeviceLine line_;  // the bus thread's only
};

}  // namespace sim_hal
