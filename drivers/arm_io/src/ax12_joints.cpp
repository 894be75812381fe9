#include "arm_io/ax12_joints.hpp"

namespace arm_io {

namespace ax12 = dynamixel::ax12;

arm::IoStatus io_status(dynamixel::BusStatus status) {
  switch (status) {
    case dynamixel::BusStatus::kOk:
      return arm::IoStatus::kOk;
    case dynamixel::BusStatus::kTimeout:
      return arm::IoStatus::kNoReply;
    case dynamixel::BusStatus::kBadChecksum:
    case dynamixel::BusStatus::kWrongReply:
      return arm::IoStatus::kCorrupt;
    case dynamixel::BusStatus::kSerialError:
      return arm::IoStatus::kPortError;
    case dynamixel::BusStatus::kInvalidArgument:
      return arm::IoStatus::kInvalid;
  }
  return arm::IoStatus::kInvalid;
}

namespace {

// A command's result: a transport failure, or an answer with error bits.
arm::IoResult command_result(const dynamixel::BusResult& r, arm::Device device) {
  if (r.status != dynamixel::BusStatus::kOk) return {io_status(r.status), device, 0};
  if (r.servo_error != 0) return {arm::IoStatus::kDeviceError, device, r.servo_error};
  return {arm::IoStatus::kOk, device, 0};
}

}  // namespace

Ax12Joints::Ax12Joints(dynamixel::Bus& bus, const JointServoConfig& config)
    : bus_(bus), config_(config), tilt_(bus, config.tilt_id), pan_(bus, config.pan_id) {}

arm::IoResult Ax12Joints::read(arm::JointReading* reading) {
  ax12::ServoState tilt, pan;
  const dynamixel::BusResult rt = tilt_.read_state(&tilt);
  if (rt.status != dynamixel::BusStatus::kOk) {
    return {io_status(rt.status), arm::Device::kTiltServo, 0};
  }
  const dynamixel::BusResult rp = pan_.read_state(&pan);
  if (rp.status != dynamixel::BusStatus::kOk) {
    return {io_status(rp.status), arm::Device::kPanServo, 0};
  }
  // A read that arrives carries good data even with error bits set: the
  // bits go into the reading for the sequence to judge.
  reading->q.tilt_rad = config_.tilt_sign * (tilt.position_rad - config_.tilt_offset_rad);
  reading->q.pan_rad = config_.pan_sign * (pan.position_rad - config_.pan_offset_rad);
  reading->moving = tilt.moving || pan.moving;
  reading->tilt_load = tilt.load_fraction;
  reading->pan_load = pan.load_fraction;
  reading->tilt_temperature_c = tilt.temperature_c;
  reading->pan_temperature_c = pan.temperature_c;
  reading->tilt_error_bits = rt.servo_error;
  reading->pan_error_bits = rp.servo_error;
  return {};
}

arm::IoResult Ax12Joints::move_servo(ax12::Servo& servo, arm::Device device, double servo_rad,
                                     double speed_rad_s) {
  const std::uint16_t pos = ax12::position_units(servo_rad);
  const std::uint16_t speed = ax12::speed_units(speed_rad_s);
  const std::uint8_t data[4] = {
      static_cast<std::uint8_t>(pos & 0xFF), static_cast<std::uint8_t>(pos >> 8),
      static_cast<std::uint8_t>(speed & 0xFF), static_cast<std::uint8_t>(speed >> 8)};
  return command_result(bus_.write(servo.id(), ax12::kGoalPosition, data, 4), device);
}

arm::IoResult Ax12Joints::move_to(const arm::JointAngles& goal, double speed_rad_s) {
  const double tilt_servo = config_.tilt_sign * goal.tilt_rad + config_.tilt_offset_rad;
  const double pan_servo = config_.pan_sign * goal.pan_rad + config_.pan_offset_rad;
  const arm::IoResult r = move_servo(tilt_, arm::Device::kTiltServo, tilt_servo, speed_rad_s);
  if (!r.ok()) return r;
  return move_servo(pan_, arm::Device::kPanServo, pan_servo, speed_rad_s);
}

arm::IoResult Ax12Joints::set_torque(bool on) {
  arm::IoResult r = command_result(tilt_.set_torque_enable(on), arm::Device::kTiltServo);
  // Torque off goes to both servos even when the first one fails.
  const arm::IoResult rp = command_result(pan_.set_torque_enable(on), arm::Device::kPanServo);
  return r.ok() ? rp : r;
}

arm::IoResult Ax12Joints::recover_servo(ax12::Servo& servo, arm::Device device) {
  const dynamixel::BusResult ping = bus_.ping(servo.id());
  if (ping.status != dynamixel::BusStatus::kOk) return {io_status(ping.status), device, 0};
  constexpr std::uint8_t kAlarm = dynamixel::kErrorOverload | dynamixel::kErrorOverheating;
  if ((ping.servo_error & kAlarm) == 0) return {};
  // Hold where it is once the torque comes back, not at a stale goal.
  std::uint16_t present = 0;
  const dynamixel::BusResult rp = bus_.read_u16(servo.id(), ax12::kPresentPosition, &present);
  if (rp.status != dynamixel::BusStatus::kOk) return {io_status(rp.status), device, 0};
  (void)bus_.write_u16(servo.id(), ax12::kGoalPosition, present);
  return command_result(servo.recover_from_alarm(), device);
}

arm::IoResult Ax12Joints::recover() {
  const arm::IoResult r = recover_servo(tilt_, arm::Device::kTiltServo);
  const arm::IoResult rp = recover_servo(pan_, arm::Device::kPanServo);
  return r.ok() ? rp : r;
}

}  // namespace arm_io
