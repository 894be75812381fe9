#pragma once
// The gripper board behind arm::GripperActuator.
#include "arm/actuators.hpp"
#include "gripper/gripper_board.hpp"

namespace arm_io {

arm::IoStatus io_status(gripper::Status status);

class GripperActuator final : public arm::GripperActuator {
 public:
  explicit GripperActuator(gripper::GripperBoard& board) : board_(board) {}

  arm::IoResult read(arm::GripperReading* reading) override;
  arm::IoResult open(double speed_fraction) override;
  arm::IoResult close(double speed_fraction, int current_limit_ma) override;
  arm::IoResult go_to(int position_counts, double speed_fraction) override;
  arm::IoResult stop() override;
  arm::IoResult calibrate() override;
  // Reads (and so clears) the latched errors, then leaves safe start.
  arm::IoResult recover() override;

 private:
  gripper::GripperBoard& board_;
};

}  // namespace arm_io
