#pragma once
// The AX-12A's control table and its quantities in SI units, over a Bus.
// Angles: 0..1023 spans 300 deg; 512 is 0 rad, counter-clockwise positive.
#include <cstddef>
#include <cstdint>

#include "dynamixel/bus.hpp"

namespace dynamixel {
namespace ax12 {

// Control-table addresses: EEPROM below 24, RAM from 24. Lock (47) set to 1
// leaves only 24..35 writable, until the servo's power is cycled (the AX-12
// manual's example 20; the refusal carries kErrorRange).
enum Address : std::uint8_t {
  kModelNumber = 0,  // 2 bytes; 12 for the AX-12A
  kFirmwareVersion = 2,
  kId = 3,
  kBaudRate = 4,     // bps = 2,000,000 / (value + 1)
  kReturnDelay = 5,  // 2 us units
  kCwAngleLimit = 6,
  kCcwAngleLimit = 8,
  kTemperatureLimit = 11,
  kMinVoltage = 12,
  kMaxVoltage = 13,
  kMaxTorque = 14,
  kStatusReturnLevel = 16,
  kAlarmLed = 17,
  kAlarmShutdown = 18,
  kTorqueEnable = 24,
  kLed = 25,
  kCwComplianceMargin = 26,
  kCcwComplianceMargin = 27,
  kCwComplianceSlope = 28,
  kCcwComplianceSlope = 29,
  kGoalPosition = 30,
  kMovingSpeed = 32,
  kTorqueLimit = 34,
  kPresentPosition = 36,
  kPresentSpeed = 38,
  kPresentLoad = 40,
  kPresentVoltage = 42,
  kPresentTemperature = 43,
  kRegistered = 44,
  kMoving = 46,
  kLock = 47,
  kPunch = 48,
  kTableSize = 50,
};

constexpr std::uint16_t kModelAx12A = 12;
constexpr double kRangeRad = 300.0 * 3.14159265358979323846 / 180.0;
constexpr double kRadPerUnit = kRangeRad / 1023.0;
constexpr double kRadPerSecPerSpeedUnit = 0.111 * 2.0 * 3.14159265358979323846 / 60.0;

std::uint16_t position_units(double angle_rad);  // clamped to 0..1023
double position_rad(std::uint16_t units);
// Moving speed: 1..1023 (0 would mean "as fast as it goes, no control").
std::uint16_t speed_units(double speed_rad_s);
// Present speed and load: bit 10 is the direction (set = clockwise).
double present_speed_rad_s(std::uint16_t raw);
double present_load_fraction(std::uint16_t raw);  // -1..1 of the maximum torque
std::uint16_t torque_units(double fraction);      // 0..1023
std::uint32_t baud_from_register(std::uint8_t value);

struct ServoState {
  double position_rad = 0.0;
  double speed_rad_s = 0.0;
  double load_fraction = 0.0;
  double voltage_v = 0.0;
  int temperature_c = 0;
  bool moving = false;
};

// One servo on a bus.
class Servo {
 public:
  Servo(Bus& bus, std::uint8_t id) : bus_(bus), id_(id) {}
  std::uint8_t id() const { return id_; }

  // Position, speed, load, voltage, temperature and the moving flag in one
  // READ of addresses 36..46.
  BusResult read_state(ServoState* state);
  BusResult read_position(double* angle_rad);
  BusResult set_goal_position(double angle_rad);
  BusResult set_moving_speed(double speed_rad_s);
  BusResult set_torque_limit(double fraction);
  BusResult set_torque_enable(bool on);
  // After an alarm shutdown (overload or overheating drops the torque limit
  // to 0): restores the torque limit from Max Torque (14) and turns torque
  // back on. While the cause persists the servo refuses, and the result
  // carries its error bits.
  BusResult recover_from_alarm();

 private:
  Bus& bus_;
  std::uint8_t id_;
};

struct ScanHit {
  std::uint8_t id = 0;
  std::uint32_t baud = 0;
  std::uint16_t model = 0;
};

// Pings every ID in [first_id, last_id] at each of the baud rates, reading
// the model number of each servo that answers. Fills at most `capacity`
// hits; returns how many. Leaves the port at the last rate tried.
std::size_t scan(Bus& bus, const std::uint32_t* bauds, std::size_t n_bauds, std::uint8_t first_id,
                 std::uint8_t last_id, ScanHit* hits, std::size_t capacity);

}  // namespace ax12
}  // namespace dynamixel
