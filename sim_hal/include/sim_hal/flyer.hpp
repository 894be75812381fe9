#pragma once
// A simulated free-flyer: a rigid body whose velocity controller follows
// the commanded linear and angular velocity (world frame) with a first-
// order lag and limited acceleration, pushed about by small random
// disturbances (air flow, cable drag): a seeded Ornstein-Uhlenbeck
// acceleration. Pure logic, time passed in.
#include <Eigen/Geometry>
#include <cstdint>

#include "sim_hal/sim_random.hpp"

namespace sim_hal {

struct FlyerParams {
  double velocity_tau_s = 0.4;   // how fast the controller follows a command
  double max_accel_mps2 = 0.08;  // Astrobee-like: gentle
  double max_angular_accel_rps2 = 0.3;
  double disturbance_mps2 = 0.004;  // standard deviation of the random push
  double disturbance_tau_s = 2.0;   // its correlation time
  double angular_disturbance_rps2 = 0.01;
};

class SimFlyer {
 public:
  SimFlyer(const Eigen::Isometry3d& T_world_body, const FlyerParams& params, std::uint64_t seed);

  // Advances by dt toward the commanded velocities (world frame).
  void step(double dt_s, const Eigen::Vector3d& v_cmd, const Eigen::Vector3d& w_cmd);
  // Held by the gripper: the pose is set from outside and the body is still.
  void hold_at(const Eigen::Isometry3d& T_world_body);

  const Eigen::Isometry3d& pose() const { return T_world_body_; }
  const Eigen::Vector3d& velocity() const { return v_; }
  const Eigen::Vector3d& angular_velocity() const { return w_; }

 private:
  Eigen::Vector3d gauss3();

  FlyerParams p_;
  Eigen::Isometry3d T_world_body_;
  Eigen::Vector3d v_ = Eigen::Vector3d::Zero(), w_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d push_ = Eigen::Vector3d::Zero(), twist_ = Eigen::Vector3d::Zero();
  SimRandom rng_;
};

}  // namespace sim_hal
