#pragma once
// What the perch sequence needs from the hardware, as two small interfaces.
// arm/ depends on no driver: drivers/arm_io implements these over the
// Dynamixel bus and the gripper board, and tests may implement them too.
// Every call returns at once with a status (no exceptions, no allocation).
#include <cstdint>

#include "arm/arm_model.hpp"

namespace arm {

enum class IoStatus : std::uint8_t {
  kOk,
  kNoReply,      // timed out after the driver's retries
  kCorrupt,      // only corrupt or wrong replies
  kPortError,    // the serial port failed
  kInvalid,      // a value the device cannot take
  kDeviceError,  // the device answered with error bits set (see IoResult)
};
const char* to_string(IoStatus status);

// Which device an IoResult is about.
enum class Device : std::uint8_t { kNone, kTiltServo, kPanServo, kGripper };
const char* to_string(Device device);

struct IoResult {
  IoStatus status = IoStatus::kOk;
  Device device = Device::kNone;
  std::uint8_t error_bits = 0;  // the device's own error bits, when it answered
  bool ok() const { return status == IoStatus::kOk; }
};

struct JointReading {
  JointAngles q;
  bool moving = false;
  double tilt_load = 0.0, pan_load = 0.0;  // fraction of the servo's maximum torque
  int tilt_temperature_c = 0, pan_temperature_c = 0;
  // The servos' error bits (Dynamixel: voltage, angle limit, overheating,
  // range, checksum, overload, instruction); 0 when healthy.
  std::uint8_t tilt_error_bits = 0, pan_error_bits = 0;
};

// The tilt and pan joints together.
class JointActuators {
 public:
  virtual ~JointActuators() = default;
  virtual IoResult read(JointReading* reading) = 0;
  // Goal angles (joint frame, rad) at a speed (rad/s), acknowledged.
  virtual IoResult move_to(const JointAngles& goal, double speed_rad_s) = 0;
  virtual IoResult set_torque(bool on) = 0;
  // After an alarm shutdown: restore the torque and enable it. Fails while
  // the cause (overload, heat) persists.
  virtual IoResult recover() = 0;
};

struct GripperReading {
  int position_counts = 0;  // from the open stop, valid once calibrated
  int current_ma = 0;
  bool calibrated = false, moving = false, holding = false, stalled = false;
  bool over_current = false, safe_start = false;
  std::uint8_t latched_error = 0;  // the board's error bits (not cleared by a read)
};

class GripperActuator {
 public:
  virtual ~GripperActuator() = default;
  virtual IoResult read(GripperReading* reading) = 0;
  virtual IoResult open(double speed_fraction) = 0;
  virtual IoResult close(double speed_fraction, int current_limit_ma) = 0;
  virtual IoResult go_to(int position_counts, double speed_fraction) = 0;
  virtual IoResult stop() = 0;
  virtual IoResult calibrate() = 0;
  // Clears latched errors and leaves safe start, so motion is accepted
  // again. Returns the errors it cleared in error_bits.
  virtual IoResult recover() = 0;
};

}  // namespace arm
