#pragma once
// The arm's two AX-12A joints behind arm::JointActuators. Joint angles map
// to servo angles through a sign and an offset (how each horn is mounted).
#include <cstdint>

#include "arm/actuators.hpp"
#include "dynamixel/ax12.hpp"
#include "dynamixel/bus.hpp"

namespace arm_io {

struct JointServoConfig {
  std::uint8_t tilt_id = 1, pan_id = 2;
  // servo angle = sign * joint angle + offset
  int tilt_sign = 1, pan_sign = 1;
  double tilt_offset_rad = 0.0, pan_offset_rad = 0.0;
};

arm::IoStatus io_status(dynamixel::BusStatus status);

class Ax12Joints final : public arm::JointActuators {
 public:
  Ax12Joints(dynamixel::Bus& bus, const JointServoConfig& config = JointServoConfig{});

  arm::IoResult read(arm::JointReading* reading) override;
  // Goal position and moving speed in one acknowledged WRITE per servo.
  arm::IoResult move_to(const arm::JointAngles& goal, double speed_rad_s) override;
  arm::IoResult set_torque(bool on) override;
  // A servo in alarm gets its goal set to where it is, then its torque
  // limit restored and torque enabled; a healthy servo is left alone.
  arm::IoResult recover() override;

 private:
  arm::IoResult move_servo(dynamixel::ax12::Servo& servo, arm::Device device, double servo_rad,
                           double speed_rad_s);
  arm::IoResult recover_servo(dynamixel::ax12::Servo& servo, arm::Device device);

  dynamixel::Bus& bus_;
  JointServoConfig config_;
  dynamixel::ax12::Servo tilt_, pan_;
};

}  // namespace arm_io
