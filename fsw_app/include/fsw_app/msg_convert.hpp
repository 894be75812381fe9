#pragma once
// Between Eigen transforms and the pose_t message; message helpers.
#include <Eigen/Geometry>

#include "hrp/arm_state_t.hpp"
#include "hrp/pose_t.hpp"

namespace fsw_app {

inline void to_msg(const Eigen::Isometry3d& T, hrp::pose_t* msg) {
  const Eigen::Quaterniond q(T.linear());
  for (int k = 0; k < 3; ++k) msg->position_m[k] = T.translation()[k];
  msg->quat_wxyz[0] = q.w();
  msg->quat_wxyz[1] = q.x();
  msg->quat_wxyz[2] = q.y();
  msg->quat_wxyz[3] = q.z();
}

inline Eigen::Isometry3d from_msg(const hrp::pose_t& msg) {
  Eigen::Quaterniond q(msg.quat_wxyz[0], msg.quat_wxyz[1], msg.quat_wxyz[2], msg.quat_wxyz[3]);
  if (q.norm() < 1e-9) q = Eigen::Quaterniond::Identity();  // an all-zero (unset) pose
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = q.normalized().toRotationMatrix();
  T.translation() = Eigen::Vector3d(msg.position_m[0], msg.position_m[1], msg.position_m[2]);
  return T;
}

inline void clear(hrp::pose_t* msg) {
  for (double& v : msg->position_m) v = 0.0;
  for (double& v : msg->quat_wxyz) v = 0.0;
}

// Gives the arm state's strings their room once, so that filling or
// decoding them later does not allocate.
inline void reserve_text(hrp::arm_state_t* msg) {
  msg->state_name.reserve(32);
  msg->fault_name.reserve(32);
  msg->fault_text.reserve(160);
  msg->last_reject_name.reserve(32);
}

}  // namespace fsw_app
