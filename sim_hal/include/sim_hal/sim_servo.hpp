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
  // Power off and on: the RAM area (24..49) back to its power-up values,
  // Lock cleared, a REG_WRITE forgotten; the EEPROM area kept.
  void power_cycle();

  // Handles one instruction addressed to this servo (or broadcast). Returns
  // true when a status packet is due, with its error byte and parameters.
  bool handle(const dynamixel::InstructionPacket& packet, std::uint8_t* error, std::uint8_t* params,
              std::size_t* n_params);
  // An instruction packet that arrived with a wrong checksum (its ID and
  // instruction as received): not carried out, but answered, as the AX-12A
  // does, with the checksum error bit and no parameters. Returns true when
  // that status packet is due (never for broadcast; the status return level
  // applies to the instruction as received).
  bool handle_bad_checksum(const dynamixel::InstructionPacket& packet, std::uint8_t* error);

  // The line rate it listens at: Baud Rate (4), bps = 2,000,000 / (value + 1).
  std::uint32_t baud_bps() const { return 2000000u / (table_[4] + 1u); }
  // Whether a host's rate is near enough to be understood: a UART tolerates
  // up to 3 % (the e-manual's note on the rates it lists, e.g. value 16,
  // 117,647 bps, for a host at 115,200).
  bool understands_baud(std::uint32_t host_bps) const;

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
  // The RAM area's values at power-up (torque limit from Max Torque, goal
  // where the shaft is).
  void init_ram();
  // Whether the status return level (16) answers this instruction.
  bool answers(std::uint8_t instruction) const;
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
