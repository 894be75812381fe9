#pragma once
// The arm task's links: the two serial ports and the drivers on them.
#include <memory>
#include <string>

#include "arm_io/ax12_joints.hpp"
#include "arm_io/gripper_actuator.hpp"
#include "dynamixel/bus.hpp"
#include "fsw_app/app_config.hpp"
#include "gripper/gripper_board.hpp"
#include "hal/clock.hpp"
#include "hal/linux_serial_port.hpp"

namespace fsw_app {

struct ArmLinks {
  hal::LinuxSerialPort servo_serial, gripper_serial;
  std::unique_ptr<dynamixel::Bus> bus;
  std::unique_ptr<gripper::GripperBoard> board;
  std::unique_ptr<arm_io::Ax12Joints> joints;
  std::unique_ptr<arm_io::GripperActuator> gripper;
};

// Opens the ports and starts the drivers; false (reported) when a port
// will not open. With sim, the simulated devices' wider margins.
bool open_arm_links(const AppConfig& cfg, const std::string& servo_port,
                    const std::string& gripper_port, bool sim, const hal::Clock& clock,
                    ArmLinks* links);

}  // namespace fsw_app
