#pragma once
// The arm task: runs the perch sequence at its rate over the actuator
// interfaces, takes PERCH_COMMAND (each one validated on receipt, in order;
// a rejection shows in ARM_STATE) and APPROACH_STATUS, and publishes
// ARM_STATE every cycle.
// It owns no port: the caller builds the drivers (real ports or the
// simulated devices' ptys) and hands over the interfaces.
#include <cstdint>

#include "arm/perch_sequence.hpp"
#include "fsw_app/lcm_hub.hpp"
#include "fsw_app/periodic_thread.hpp"
#include "hal/clock.hpp"
#include "hrp/approach_status_t.hpp"
#include "hrp/arm_state_t.hpp"
#include "hrp/perch_command_t.hpp"

namespace fsw_app {

class ArmTask {
 public:
  ArmTask(LcmHub& hub, arm::JointActuators& joints, arm::GripperActuator& gripper,
          const arm::PerchConfig& config, const hal::Clock& clock, double rate_hz,
          int rt_priority = 0);
  ~ArmTask();

  void start();
  void stop();
  // One cycle: new command, approach, sequence step, ARM_STATE.
  void cycle();

  const arm::PerchSequence& sequence() const { return sequence_; }
  const hrp::arm_state_t& last_state() const { return state_; }
  // Whether the loop ran on time (and under which scheduler).
  CycleStats cycle_stats() const { return thread_.stats(); }

 private:
  void fill_state();

  LcmHub& hub_;
  const hal::Clock& clock_;
  arm::PerchSequence sequence_;
  std::int64_t period_us_;
  int rt_priority_;
  // Every command is submitted (validated and answered), up to this many
  // per cycle; more within one 50 ms cycle is a runaway sender, and the
  // oldest are dropped and counted in ARM_STATE.commands_dropped.
  static constexpr std::size_t kCommandQueue = 8;
  MessageQueue<hrp::perch_command_t, kCommandQueue> command_queue_;
  Mailbox<hrp::approach_status_t> approach_box_;
  Publisher<hrp::arm_state_t> state_pub_;
  hrp::perch_command_t command_{};
  hrp::approach_status_t approach_{};
  hrp::arm_state_t state_{};
  std::int32_t last_sequence_ = 0;
  PeriodicThread thread_;  // last: stopped before the members it uses go
};

}  // namespace fsw_app
