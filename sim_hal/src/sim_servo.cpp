#include "sim_hal/sim_servo.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>

namespace sim_hal {
namespace {
using dynamixel::Instruction;

constexpr double kRadPerUnit = 300.0 * 3.14159265358979323846 / 180.0 / 1023.0;
constexpr double kSpeedUnitRadS = 0.111 * 2.0 * 3.14159265358979323846 / 60.0;
constexpr std::uint8_t kFirstRam = 24;  // EEPROM below
// With Lock (47) set, only Torque Enable (24) to Torque Limit (35) can be
// written (the AX-12 manual, example 20: a write to Punch then answers with
// the range error bit); only a power cycle clears it.
constexpr std::uint8_t kFirstUnlocked = 24, kLastUnlocked = 35;
constexpr std::uint8_t kLock = 47;
constexpr std::uint8_t kFirstReadOnly = 36;  // present position .. moving
constexpr std::uint8_t kTableEnd = 50;
}  // namespace

SimServo::SimServo(std::uint8_t id, const ServoPhysics& physics) : physics_(physics) {
  reset_table();
  table_[3] = id;
  temperature_c_ = physics_.ambient_c;
}

std::uint16_t SimServo::table16(std::uint8_t address) const {
  return static_cast<std::uint16_t>(table_[address] | (table_[address + 1] << 8));
}

void SimServo::set16(std::uint8_t address, std::uint16_t value) {
  table_[address] = static_cast<std::uint8_t>(value & 0xFF);
  table_[address + 1] = static_cast<std::uint8_t>(value >> 8);
}

void SimServo::reset_table() {
  const std::uint8_t id = table_[3] ? table_[3] : 1;
  std::memset(table_, 0, sizeof(table_));
  set16(0, 12);    // model AX-12A
  table_[2] = 24;  // firmware
  table_[3] = id;
  table_[4] = 1;      // 1 Mbps
  table_[5] = 250;    // 500 us return delay
  set16(6, 0);        // CW angle limit
  set16(8, 1023);     // CCW angle limit
  table_[11] = 70;    // temperature limit
  table_[12] = 60;    // 6 V
  table_[13] = 140;   // 14 V
  set16(14, 1023);    // max torque
  table_[16] = 2;     // status return level
  table_[17] = 0x24;  // alarm LED: overheating, overload
  table_[18] = 0x24;  // alarm shutdown: overheating, overload
  init_ram();
}

void SimServo::init_ram() {
  std::memset(table_ + kFirstRam, 0, kTableEnd - kFirstRam);
  table_[26] = table_[27] = 1;
  table_[28] = table_[29] = 32;
  set16(34, table16(14));  // torque limit: copied from max torque at power-up
  set16(48, 32);           // punch
  const std::uint16_t here = static_cast<std::uint16_t>(
      std::clamp(std::lround(512.0 + position_rad_ / kRadPerUnit), 0L, 1023L));
  set16(30, here);  // goal = present: no jump at power-up
  set16(36, here);
  table_[42] = static_cast<std::uint8_t>(std::lround(physics_.supply_v * 10.0));
  table_[43] = static_cast<std::uint8_t>(std::lround(temperature_c_));
  pending_n_ = 0;
}

void SimServo::power_cycle() {
  init_ram();
  // Latched alarms are the firmware's state and go with the power; a cause
  // still present (heat, load) raises them again.
  overloaded_ = false;
  overload_s_ = 0.0;
  speed_rad_s_ = 0.0;
}

bool SimServo::understands_baud(std::uint32_t host_bps) const {
  const double own = static_cast<double>(baud_bps());
  return std::fabs(static_cast<double>(host_bps) - own) <= 0.03 * own;
}

bool SimServo::answers(std::uint8_t instruction) const {
  const Instruction inst = static_cast<Instruction>(instruction);
  switch (table_[16]) {
    case 0:
      return inst == Instruction::kPing;
    case 1:
      return inst == Instruction::kPing || inst == Instruction::kRead;
    default:
      return true;
  }
}

std::uint8_t SimServo::error_bits() const {
  std::uint8_t e = forced_errors_;
  if (overheated_) e |= dynamixel::kErrorOverheating;
  if (overloaded_) e |= dynamixel::kErrorOverload;
  const double v10 = physics_.supply_v * 10.0;
  if (v10 < table_[12] || v10 > table_[13]) e |= dynamixel::kErrorInputVoltage;
  return e;
}

void SimServo::alarm_shutdown_if_needed() {
  if (error_bits() & table_[18]) {
    // What a real servo does: torque limit to 0 (torque off in effect).
    set16(34, 0);
  }
}

std::uint8_t SimServo::apply_write(std::uint8_t address, const std::uint8_t* data, std::size_t n) {
  if (address >= kTableEnd || address + n > kTableEnd) return dynamixel::kErrorRange;
  const bool locked = table_[kLock] != 0;
  for (std::size_t k = 0; k < n; ++k) {
    const std::uint8_t a = static_cast<std::uint8_t>(address + k);
    if (locked && (a < kFirstUnlocked || a > kLastUnlocked)) return dynamixel::kErrorRange;
    if (a >= kFirstReadOnly && a != kLock && a != 48 && a != 49) return dynamixel::kErrorRange;
    if (a < 3) return dynamixel::kErrorRange;  // model and firmware
    if (a == kLock && data[k] > 1) return dynamixel::kErrorRange;
  }
  // A goal outside the angle limits is refused with the angle-limit bit.
  if (address <= 31 && address + n >= 32) {
    std::uint8_t b[2] = {table_[30], table_[31]};
    for (std::size_t k = 0; k < n; ++k) {
      if (address + k == 30) b[0] = data[k];
      if (address + k == 31) b[1] = data[k];
    }
    const std::uint16_t goal = static_cast<std::uint16_t>(b[0] | (b[1] << 8));
    const std::uint16_t cw = table16(6), ccw = table16(8);
    if (goal > 1023 || ((cw || ccw) && (goal < cw || goal > ccw))) {
      return dynamixel::kErrorAngleLimit;
    }
  }
  for (std::size_t k = 0; k < n; ++k) table_[address + k] = data[k];
  if (table16(34) > 1023) set16(34, 1023);
  // The documented recovery from an overload shutdown: with the cause gone,
  // a non-zero torque limit.
  if (address <= 35 && address + n > 34 && table16(34) > 0 && !overload_cause_) {
    overloaded_ = false;
    overload_s_ = 0.0;
  }
  return 0;
}

bool SimServo::handle(const dynamixel::InstructionPacket& packet, std::uint8_t* error,
                      std::uint8_t* params, std::size_t* n_params) {
  *n_params = 0;
  std::uint8_t err = 0;
  const bool broadcast = packet.id == dynamixel::kBroadcastId;
  switch (static_cast<Instruction>(packet.instruction)) {
    case Instruction::kPing:
      break;
    case Instruction::kRead: {
      if (packet.n_params != 2) {
        err = dynamixel::kErrorInstruction;
        break;
      }
      const std::uint8_t address = packet.params[0], length = packet.params[1];
      if (address + length > kTableEnd || length == 0) {
        err = dynamixel::kErrorRange;
        break;
      }
      std::memcpy(params, table_ + address, length);
      *n_params = length;
      break;
    }
    case Instruction::kWrite:
      if (packet.n_params < 2) {
        err = dynamixel::kErrorInstruction;
        break;
      }
      err = apply_write(packet.params[0], packet.params + 1, packet.n_params - 1u);
      break;
    case Instruction::kRegWrite:
      if (packet.n_params < 2) {
        err = dynamixel::kErrorInstruction;
        break;
      }
      std::memcpy(pending_, packet.params, packet.n_params);
      pending_n_ = packet.n_params;
      table_[44] = 1;
      break;
    case Instruction::kAction:
      if (pending_n_ == 0) {
        err = dynamixel::kErrorInstruction;  // ACTION with nothing registered
        break;
      }
      err = apply_write(pending_[0], pending_ + 1, pending_n_ - 1);
      pending_n_ = 0;
      table_[44] = 0;
      break;
    case Instruction::kReset:
      // Factory defaults would rewrite the EEPROM the lock protects: while
      // locked the servo refuses (our reading; the manuals say only that a
      // locked servo unlocks by a power cycle alone).
      if (table_[kLock]) {
        err = dynamixel::kErrorRange;
        break;
      }
      reset_table();
      break;
    case Instruction::kSyncWrite: {
      // FE; addr, L, then [ID, L bytes] per servo: find this one's.
      if (packet.n_params < 2) return false;
      const std::uint8_t address = packet.params[0], length = packet.params[1];
      for (std::size_t k = 2; k + length < packet.n_params + 1u; k += length + 1u) {
        if (packet.params[k] == id()) apply_write(address, packet.params + k + 1, length);
      }
      return false;
    }
    default:
      err = dynamixel::kErrorInstruction;
      break;
  }
  alarm_shutdown_if_needed();
  *error = static_cast<std::uint8_t>(err | error_bits());
  if (broadcast) return false;
  return answers(packet.instruction);
}

bool SimServo::handle_bad_checksum(const dynamixel::InstructionPacket& packet,
                                   std::uint8_t* error) {
  *error = static_cast<std::uint8_t>(dynamixel::kErrorChecksum | error_bits());
  if (packet.id == dynamixel::kBroadcastId) return false;
  return answers(packet.instruction);
}

void SimServo::step(double dt_s, double external_torque_nm) {
  if (dt_s <= 0.0) return;
  const double torque_limit = table16(34) / 1023.0 * table16(14) / 1023.0;
  const bool torque_on = table_[24] != 0 && torque_limit > 0.0;
  const double available_nm = torque_on ? physics_.stall_torque_nm * torque_limit : 0.0;
  const double goal = (static_cast<double>(table16(30)) - 512.0) * kRadPerUnit;
  const std::uint16_t speed_units = table16(32);
  const double max_speed = physics_.no_load_speed_rad_s * physics_.supply_v / 12.0;
  const double commanded_speed =
      speed_units == 0 ? max_speed : std::min(max_speed, speed_units * kSpeedUnitRadS);
  // The load is what the motor must hold against; a torque beyond what it
  // may give stalls (or back-drives) it.
  const double load_nm = -external_torque_nm;
  load_fraction_ = std::clamp(load_nm / physics_.stall_torque_nm, -1.0, 1.0);
  if (torque_on && std::fabs(load_nm) <= available_nm) {
    const double error = goal - position_rad_;
    // Speed falls linearly with load, as a DC motor's does.
    const double speed = commanded_speed * (1.0 - std::fabs(load_nm) / physics_.stall_torque_nm);
    const double move = std::clamp(error, -speed * dt_s, speed * dt_s);
    position_rad_ += move;
    speed_rad_s_ = move / dt_s;
  } else if (std::fabs(external_torque_nm) > available_nm) {
    // Back-driven at a slow creep in the torque's direction.
    const double creep = 0.2 * (external_torque_nm > 0 ? 1.0 : -1.0);
    position_rad_ += creep * dt_s;
    speed_rad_s_ = creep;
  } else {
    speed_rad_s_ = 0.0;
  }
  position_rad_ = std::clamp(position_rad_, -512.0 * kRadPerUnit, 511.0 * kRadPerUnit);

  // Heat from the load, cooling toward ambient.
  temperature_c_ += dt_s * (physics_.heating_c_per_s * load_fraction_ * load_fraction_ -
                            (temperature_c_ - physics_.ambient_c) / physics_.cooling_tau_s);
  overheated_ = temperature_c_ > table_[11] || (forced_errors_ & dynamixel::kErrorOverheating);
  const bool over = torque_on && std::fabs(load_nm) > available_nm;
  overload_s_ = over ? overload_s_ + dt_s : 0.0;
  // The cause: more load than the servo can give at its maximum torque.
  overload_cause_ = std::fabs(load_nm) > physics_.stall_torque_nm * table16(14) / 1023.0 ||
                    (forced_errors_ & dynamixel::kErrorOverload);
  // An overload latches until the torque limit is written again.
  if (overload_s_ > physics_.overload_hold_s || (forced_errors_ & dynamixel::kErrorOverload)) {
    overloaded_ = true;
  }
  alarm_shutdown_if_needed();

  // The read-only part of the table.
  const long units = std::lround(512.0 + position_rad_ / kRadPerUnit);
  set16(36, static_cast<std::uint16_t>(std::clamp(units, 0L, 1023L)));
  const long speed = std::min(1023L, std::lround(std::fabs(speed_rad_s_) / kSpeedUnitRadS));
  set16(38, static_cast<std::uint16_t>(speed | (speed_rad_s_ < 0 ? 0x400 : 0)));
  const long load = std::min(1023L, std::lround(std::fabs(load_fraction_) * 1023.0));
  set16(40, static_cast<std::uint16_t>(load | (load_fraction_ < 0 ? 0x400 : 0)));
  table_[42] = static_cast<std::uint8_t>(std::lround(physics_.supply_v * 10.0));
  table_[43] = static_cast<std::uint8_t>(std::clamp(std::lround(temperature_c_), 0L, 255L));
  table_[46] = std::fabs(goal - position_rad_) > kRadPerUnit && torque_on ? 1 : 0;
}

void SimServo::set_position_rad(double angle_rad) {
  position_rad_ = std::clamp(angle_rad, -512.0 * kRadPerUnit, 511.0 * kRadPerUnit);
  const long units = std::lround(512.0 + position_rad_ / kRadPerUnit);
  set16(30, static_cast<std::uint16_t>(std::clamp(units, 0L, 1023L)));
  set16(36, static_cast<std::uint16_t>(std::clamp(units, 0L, 1023L)));
}

}  // namespace sim_hal
