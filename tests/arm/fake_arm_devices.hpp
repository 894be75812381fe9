#pragma once
// In-memory joints and gripper board for the perch sequence's logic tests:
// just enough physics (constant-speed motion, hard stops, a handrail that
// stops the fingers) and every fault the sequence must handle, switched by
// fields. Time comes from the test's ManualClock. The same sequence runs
// against the real drivers and simulated devices over ptys in
// test_perch_hil.cpp.
#include <algorithm>
#include <cmath>

#include "arm/actuators.hpp"
#include "hal/clock.hpp"

struct FakeJoints final : arm::JointActuators {
  explicit FakeJoints(const hal::Clock& clock) : clock_(clock) {}
  arm::JointAngles q{M_PI / 2, 0.0}, goal{M_PI / 2, 0.0};
  double speed_rad_s = 1.0;
  bool torque = false, silent = false, stuck = false;
  std::uint8_t error_bits = 0;  // reported by the tilt servo
  int moves = 0, torque_offs = 0, recovers = 0;

  void advance() {
    const double dt = 1e-6 * static_cast<double>(clock_.now_us() - last_us_);
    last_us_ = clock_.now_us();
    if (!torque || stuck || error_bits) return;
    const double step = speed_rad_s * dt;
    q.tilt_rad += std::clamp(goal.tilt_rad - q.tilt_rad, -step, step);
    q.pan_rad += std::clamp(goal.pan_rad - q.pan_rad, -step, step);
  }
  arm::IoResult read(arm::JointReading* r) override {
    advance();
    if (silent) return {arm::IoStatus::kNoReply, arm::Device::kTiltServo, 0};
    r->q = q;
    r->moving = torque && !stuck && !error_bits &&
                (std::fabs(goal.tilt_rad - q.tilt_rad) > 1e-3 ||
                 std::fabs(goal.pan_rad - q.pan_rad) > 1e-3);
    r->tilt_error_bits = error_bits;
    r->pan_error_bits = 0;
    return {};
  }
  arm::IoResult move_to(const arm::JointAngles& g, double speed) override {
    advance();
    if (silent) return {arm::IoStatus::kNoReply, arm::Device::kTiltServo, 0};
    if (error_bits) return {arm::IoStatus::kDeviceError, arm::Device::kTiltServo, error_bits};
    goal = g;
    speed_rad_s = speed;
    ++moves;
    return {};
  }
  arm::IoResult set_torque(bool on) override {
    if (silent) return {arm::IoStatus::kNoReply, arm::Device::kTiltServo, 0};
    torque = on;
    if (!on) ++torque_offs;
    return {};
  }
  arm::IoResult recover() override {
    ++recovers;
    if (silent) return {arm::IoStatus::kNoReply, arm::Device::kTiltServo, 0};
    return {};
  }

 private:
  const hal::Clock& clock_;
  std::int64_t last_us_ = 0;
};

struct FakeGripper final : arm::GripperActuator {
  explicit FakeGripper(const hal::Clock& clock) : clock_(clock) {}
  double position = 2000.0, target = 2000.0, speed_counts_s = 3000.0;
  int handrail_counts = -1;  // where closing stops; -1: nothing there
  bool calibrated = false, safe_start = true, silent = false, over_current = false;
  bool holding = false, closing = false;
  std::uint8_t latched = 0;
  int calibrations = 0, stops = 0, opens = 0, closes = 0;
  int lost_commands = 0;  // the next this many motion commands are lost on the line

  // A command whose packet was mangled: the board never acted on it.
  bool lose_command() {
    if (lost_commands <= 0) return false;
    --lost_commands;
    return true;
  }

  void advance() {
    const double dt = 1e-6 * static_cast<double>(clock_.now_us() - last_us_);
    last_us_ = clock_.now_us();
    const double step = speed_counts_s * dt;
    double goal = target;
    if (closing && handrail_counts >= 0) goal = std::min<double>(goal, handrail_counts);
    position += std::clamp(goal - position, -step, step);
    if (calibrating_ && std::fabs(position - target) < 1.0) {
      calibrating_ = false;
      calibrated = true;
      position = target = 0.0;
    }
    holding = closing && std::fabs(position - goal) < 1.0;
  }
  arm::IoResult read(arm::GripperReading* r) override {
    advance();
    if (silent) return {arm::IoStatus::kNoReply, arm::Device::kGripper, 0};
    r->position_counts = static_cast<int>(std::lround(position));
    r->current_ma = holding ? 800 : 150;
    r->calibrated = calibrated;
    r->moving = std::fabs(position - (closing && handrail_counts >= 0
                                          ? std::min<double>(target, handrail_counts)
                                          : target)) >= 1.0;
    r->holding = holding;
    r->stalled = false;
    r->over_current = over_current;
    r->safe_start = safe_start;
    r->latched_error = latched;
    return {};
  }
  arm::IoResult motion(double new_target, bool close) {
    advance();
    if (silent) return {arm::IoStatus::kNoReply, arm::Device::kGripper, 0};
    if (lose_command()) return {arm::IoStatus::kCorrupt, arm::Device::kGripper, 0};
    if (safe_start) return {};  // refused on the board, as the real one does
    target = new_target;
    closing = close;
    return {};
  }
  arm::IoResult open(double) override {
    ++opens;
    return motion(0.0, false);
  }
  arm::IoResult close(double, int) override {
    ++closes;
    return motion(3000.0, true);
  }
  arm::IoResult go_to(int counts, double) override {
    if (!calibrated) return {};  // the board latches NOT_CALIBRATED and ignores it
    return motion(counts, false);
  }
  arm::IoResult stop() override {
    ++stops;
    advance();
    if (silent) return {arm::IoStatus::kNoReply, arm::Device::kGripper, 0};
    target = position;
    closing = false;
    return {};
  }
  arm::IoResult calibrate() override {
    ++calibrations;
    advance();
    if (silent) return {arm::IoStatus::kNoReply, arm::Device::kGripper, 0};
    if (lose_command()) return {arm::IoStatus::kCorrupt, arm::Device::kGripper, 0};
    if (safe_start) return {};
    calibrated = false;
    calibrating_ = true;
    closing = false;
    target = position - 4000.0;  // somewhere beyond the open stop
    target = std::max(target, -500.0);
    return {};
  }
  arm::IoResult recover() override {
    if (silent) return {arm::IoStatus::kNoReply, arm::Device::kGripper, 0};
    latched = 0;
    safe_start = false;
    over_current = false;
    return {};
  }

 private:
  const hal::Clock& clock_;
  std::int64_t last_us_ = 0;
  bool calibrating_ = false;
};
