#pragma once
// A simulated gripper board on a pseudo-terminal: the real firmware logic
// (drivers/gripper/firmware, built for the host) driving a model of the
// gearmotor, its encoder and current sense, the fingers' hard stops, and
// optionally a handrail between the fingers that stalls them as they close.
#include <atomic>
#include <cstdint>
#include <mutex>
#include <string>
#include <thread>

#include "gripper_fw.h"
#include "hal/clock.hpp"
#include "sim_hal/device_line.hpp"
#include "sim_hal/pty.hpp"

namespace sim_hal {

struct GripperModel {
  double supply_v = 12.0;
  double winding_ohm = 6.0;           // stall current 2 A at 12 V
  double free_speed_counts_s = 3000;  // full travel in about a second
  double time_constant_s = 0.02;      // mechanical
  int open_stop_raw = -500;           // encoder counts; 0 at power-up
  int closed_stop_raw = 2500;         // the fingers meet (an empty grasp)
};

struct GripperSnapshot {
  double position_raw = 0.0, velocity_counts_s = 0.0, current_a = 0.0;
  int pwm = 0;
  bool calibrated = false, safe_start = true;
};

class SimGripperBoard {
 public:
  explicit SimGripperBoard(const GripperModel& model = GripperModel{});
  ~SimGripperBoard();

  bool start(std::string* error);
  void stop();
  const std::string& path() const { return pty_.slave_path(); }

  // A handrail between the fingers: closing stops at this raw encoder
  // count; a negative value removes it.
  void set_handrail_raw(int raw);
  void set_faults(const BusFaults& faults);
  // A shorted winding: while driven, the motor draws four times its
  // normal current, enough to trip the board's absolute limit.
  void set_winding_short(bool shorted);
  GripperSnapshot snapshot() const;

 private:
  void run();
  void step_motor(double dt_s, int pwm);

  GripperModel model_;
  PtyDevice pty_;
  hal::MonotonicClock clock_;
  std::thread thread_;
  std::atomic<bool> running_{false};
  mutable std::mutex mutex_;  // guards everything below
  gfw_state fw_{};
  double position_ = 0.0, velocity_ = 0.0, current_a_ = 0.0;
  int handrail_raw_ = -1;
  bool winding_short_ = false;
  BusFaults faults_;
  DeviceLine line_{7};  // the board thread's only
};

}  // namespace sim_hal
