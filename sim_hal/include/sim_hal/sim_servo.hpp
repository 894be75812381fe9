#pragma once
// A simulated Dynamixel AX-12A: its control table with the real servo's
// rules, and a motion model. Pure logic with time passed in; SimServoBus
// (sim_servo_bus.hpp) serves a set of them on a pseudo-terminal.
#include <cstddef>
#include <cstdint>

#include "dynamixel/protocol1.hpp"

namespace sim_hal {

struct ServoPhysics {
  double stall_torque_nm = 1.5;       // at 12 V
  double no_load_speed_rad_s = 6.18;  // 59 rpm at 12 V
  double ambient_c = 30.0;
  // First-order heating: degrees per second per (load fraction)^2, and the
  // cooling time constant.
  double heating_c_per_s = 6.0;
  double cooling_tau_s = 120.0;
  double overload_hold_s = 0.3;  // a load above the torque limit this long is an overload
  double supply_v = 12.0;
};

class SimServo {
 public:
  explicit SimServo(std::uint8_t id = 1, const ServoPhysics& physics = ServoPhysics{});

  // Factory defaults (the ID is kept, as RESET of a real servo gives ID 1
  // only when asked; the simulator keeps buses stable).
  void reset_table();

  // Handles one instruction addressed to this servo (or broadcast). Returns
  // true when a status packet is due, with its error byte and parameters.
  bool handle(const dynamixel::InstructionPacket& packet, std::uint8_t* error, std::uint8_t* params,
              std::size_t* n_params);

  // Advances the motion model by dt with an external torque on the output
  // (N m, positive counter-clockwise).
  void step(double dt_s, double external_torque_nm);

  std::uint8_t id() const { return table_[3]; }
  // The error bits it reports now (sticky causes: overheating, overload).
  std::uint8_t error_bits() const;
  std::uint8_t table(std::uint8_t address) const { return table_[address]; }
  std::uint16_t table16(std::uint8_t address) const;
  double position_rad() const { return position_rad_; }
  double temperature_c() const { return temperature_c_; }
  std::uint32_t return_delay_us() const { return 2u * table_[5]; }
  // Faults forced from outside (fault injection): OR-ed into the error byte
  // and acted on as the real causes would be.
  void force_error_bits(std::uint8_t bits) { forced_errors_ = bits; }
  // Puts the output shaft at an angle (where the arm was left), goal too.
  void set_position_rad(double angle_rad);

 private:
  // Applies a write of n bytes at address; returns the error bits it raises.
  std::uint8_t apply_write(std::uint8_t address, const std::uint8_t* data, std::size_t n);
  void set16(std::uint8_t address, std::uint16_t value);
  void alarm_shutdown_if_needed();

  ServoPhysics physics_;
  std::uint8_t table_[50] = {};
  double position_rad_ = 0.0, speed_rad_s_ = 0.0, temperature_c_ = 30.0, overload_s_ = 0.0;
  double load_fraction_ = 0.0;
  bool overheated_ = false, overloaded_ = false, overload_cause_ = false;
  std::uint8_t forced_errors_ = 0;
  // A REG_WRITE waiting for ACTION.
  std::uint8_t pending_[dynamixel::kMaxParams] = {};
  std::size_t pending_n_ = 0;
};

}  // namespace sim_hal
