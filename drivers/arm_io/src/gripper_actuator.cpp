#include "arm_io/gripper_actuator.hpp"

namespace arm_io {

arm::IoStatus io_status(gripper::Status status) {
  switch (status) {
    case gripper::Status::kOk:
      return arm::IoStatus::kOk;
    case gripper::Status::kTimeout:
      return arm::IoStatus::kNoReply;
    case gripper::Status::kBadCrc:
      return arm::IoStatus::kCorrupt;
    case gripper::Status::kSerialError:
      return arm::IoStatus::kPortError;
    case gripper::Status::kInvalidArgument:
      return arm::IoStatus::kInvalid;
  }
  return arm::IoStatus::kInvalid;
}

namespace {

arm::IoResult result(gripper::Status s) {
  return {io_status(s), arm::Device::kGripper, 0};
}

}  // namespace

arm::IoResult GripperActuator::read(arm::GripperReading* reading) {
  gripper::State st;
  const gripper::Status s = board_.get_state(&st);
  if (s != gripper::Status::kOk) return result(s);
  reading->position_counts = st.position_counts;
  reading->current_ma = st.current_ma;
  reading->calibrated = st.has(gripper::kFlagCalibrated);
  reading->moving = st.has(gripper::kFlagMoving);
  reading->holding = st.has(gripper::kFlagHolding);
  reading->stalled = st.has(gripper::kFlagStalled);
  reading->over_current = st.has(gripper::kFlagOverCurrent);
  reading->safe_start = st.has(gripper::kFlagSafeStart);
  reading->latched_error = st.error;
  return result(s);
}

arm::IoResult GripperActuator::open(double speed_fraction) {
  return result(board_.open(speed_fraction));
}

arm::IoResult GripperActuator::close(double speed_fraction, int current_limit_ma) {
  return result(board_.close(speed_fraction, current_limit_ma));
}

arm::IoResult GripperActuator::go_to(int position_counts, double speed_fraction) {
  return result(board_.go_to(position_counts, speed_fraction));
}

arm::IoResult GripperActuator::stop() {
  return result(board_.stop());
}

arm::IoResult GripperActuator::calibrate() {
  return result(board_.calibrate());
}

arm::IoResult GripperActuator::recover() {
  std::uint8_t cleared = 0;
  const gripper::Status s = board_.get_error(&cleared);
  if (s != gripper::Status::kOk) return result(s);
  arm::IoResult r = result(board_.exit_safe_start());
  r.error_bits = cleared;
  return r;
}

}  // namespace arm_io
