#include "dynamixel/ax12.hpp"

#include <cmath>

namespace dynamixel {
namespace ax12 {

std::uint16_t position_units(double angle_rad) {
  const double units = std::round(512.0 + angle_rad / kRadPerUnit);
  if (!(units >= 0.0)) return 0;  // also NaN
  return static_cast<std::uint16_t>(units > 1023.0 ? 1023.0 : units);
}

double position_rad(std::uint16_t units) {
  return (static_cast<double>(units) - 512.0) * kRadPerUnit;
}

std::uint16_t speed_units(double speed_rad_s) {
  const double units = std::round(std::fabs(speed_rad_s) / kRadPerSecPerSpeedUnit);
  if (!(units >= 1.0)) return 1;
  return static_cast<std::uint16_t>(units > 1023.0 ? 1023.0 : units);
}

double present_speed_rad_s(std::uint16_t raw) {
  const double magnitude = static_cast<double>(raw & 0x3FF) * kRadPerSecPerSpeedUnit;
  return (raw & 0x400) ? -magnitude : magnitude;
}

double present_load_fraction(std::uint16_t raw) {
  const double magnitude = static_cast<double>(raw & 0x3FF) / 1023.0;
  return (raw & 0x400) ? -magnitude : magnitude;
}

std::uint16_t torque_units(double fraction) {
  const double units = std::round(fraction * 1023.0);
  if (!(units >= 0.0)) return 0;
  return static_cast<std::uint16_t>(units > 1023.0 ? 1023.0 : units);
}

std::uint32_t baud_from_register(std::uint8_t value) {
  return 2000000u / (value + 1u);
}

BusResult Servo::read_state(ServoState* state) {
  std::uint8_t b[kMoving - kPresentPosition + 1];
  const BusResult r = bus_.read(id_, kPresentPosition, sizeof(b), b);
  if (r.status != BusStatus::kOk) return r;
  auto u16 = [&](int address) {
    const int k = address - kPresentPosition;
    return static_cast<std::uint16_t>(b[k] | (b[k + 1] << 8));
  };
  state->position_rad = position_rad(u16(kPresentPosition));
  state->speed_rad_s = present_speed_rad_s(u16(kPresentSpeed));
  state->load_fraction = present_load_fraction(u16(kPresentLoad));
  state->voltage_v = 0.1 * b[kPresentVoltage - kPresentPosition];
  state->temperature_c = b[kPresentTemperature - kPresentPosition];
  state->moving = b[kMoving - kPresentPosition] != 0;
  return r;
}

BusResult Servo::read_position(double* angle_rad) {
  std::uint16_t units = 0;
  const BusResult r = bus_.read_u16(id_, kPresentPosition, &units);
  if (r.status == BusStatus::kOk) *angle_rad = position_rad(units);
  return r;
}

BusResult Servo::set_goal_position(double angle_rad) {
  return bus_.write_u16(id_, kGoalPosition, position_units(angle_rad));
}

BusResult Servo::set_moving_speed(double speed_rad_s) {
  return bus_.write_u16(id_, kMovingSpeed, speed_units(speed_rad_s));
}

BusResult Servo::set_torque_limit(double fraction) {
  return bus_.write_u16(id_, kTorqueLimit, torque_units(fraction));
}

BusResult Servo::set_torque_enable(bool on) {
  return bus_.write_u8(id_, kTorqueEnable, on ? 1 : 0);
}

BusResult Servo::recover_from_alarm() {
  std::uint16_t max_torque = 0;
  BusResult r = bus_.read_u16(id_, kMaxTorque, &max_torque);
  if (r.status != BusStatus::kOk) return r;
  // The alarm bits latch until the torque limit is written again, so only
  // the reply to that write says whether the cause is gone: if the servo
  // still reports overload or overheating, it has shut down again.
  r = bus_.write_u16(id_, kTorqueLimit, max_torque ? max_torque : 1023);
  if (r.status != BusStatus::kOk || (r.servo_error & (kErrorOverload | kErrorOverheating))) {
    return r;
  }
  return bus_.write_u8(id_, kTorqueEnable, 1);
}

std::size_t scan(Bus& bus, const std::uint32_t* bauds, std::size_t n_bauds, std::uint8_t first_id,
                 std::uint8_t last_id, ScanHit* hits, std::size_t capacity) {
  std::size_t found = 0;
  // A missing ID is the common case in a scan: no retries.
  const BusConfig saved = bus.config();
  BusConfig quick = saved;
  quick.retries = 0;
  bus.set_config(quick);
  for (std::size_t b = 0; b < n_bauds; ++b) {
    if (bus.port().set_baud(bauds[b]) != hal::SerialStatus::kOk) continue;
    for (unsigned id = first_id; id <= last_id && id < kBroadcastId; ++id) {
      const std::uint8_t sid = static_cast<std::uint8_t>(id);
      if (bus.ping(sid).status != BusStatus::kOk) continue;
      std::uint16_t model = 0;
      bus.read_u16(sid, kModelNumber, &model);
      if (found < capacity) hits[found] = {sid, bauds[b], model};
      ++found;
    }
  }
  bus.set_config(saved);
  return found < capacity ? found : capacity;
}

}  // namespace ax12
}  // namespace dynamixel
