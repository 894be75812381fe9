#include "arm_links.hpp"

#include <algorithm>
#include <cstdio>

namespace fsw_app {

bool open_arm_links(const AppConfig& cfg, const std::string& servo_port,
                    const std::string& gripper_port, bool sim, const hal::Clock& clock,
                    ArmLinks* links) {
  std::string error;
  if (links->servo_serial.open(servo_port, cfg.ports.servo_baud, &error) !=
      hal::SerialStatus::kOk) {
    std::fprintf(stderr, "fsw_app: servo bus: %s\n", error.c_str());
    return false;
  }
  if (links->gripper_serial.open(gripper_port, cfg.ports.gripper_baud, &error) !=
      hal::SerialStatus::kOk) {
    std::fprintf(stderr, "fsw_app: gripper board: %s\n", error.c_str());
    return false;
  }
  dynamixel::BusConfig bus_cfg;
  bus_cfg.return_delay_us = cfg.ports.servo_return_delay_us;
  // The simulated devices are threads of this process on a host that may
  // be shared (a virtual machine with steal time): their replies get a
  // wider margin than the wire needs, and the board a longer serial
  // timeout, so that a stalled host does not pass for a failed line.
  bus_cfg.margin_us = sim ? 100000 : cfg.ports.servo_margin_us;
  links->bus = std::make_unique<dynamixel::Bus>(links->servo_serial, clock, bus_cfg);
  links->board = std::make_unique<gripper::GripperBoard>(
      links->gripper_serial, clock, 2, sim ? 120000 : cfg.ports.gripper_margin_us);
  const std::uint32_t serial_timeout_ms =
      sim ? std::max<std::uint32_t>(cfg.ports.gripper_serial_timeout_ms, 2000)
          : cfg.ports.gripper_serial_timeout_ms;
  if (const gripper::Status s = links->board->set_timeout_ms(static_cast<int>(serial_timeout_ms));
      s != gripper::Status::kOk) {
    std::fprintf(stderr,
                 "fsw_app: gripper board on %s: could not set its serial timeout to %u ms (%s); "
                 "it keeps its own (500 ms after a reset)\n",
                 gripper_port.c_str(), serial_timeout_ms, gripper::to_string(s));
  }
  links->joints = std::make_unique<arm_io::Ax12Joints>(*links->bus, cfg.servos);
  links->gripper = std::make_unique<arm_io::GripperActuator>(*links->board);
  return true;
}

}  // namespace fsw_app
