#include "arm/arm_model.hpp"

#include <algorithm>
#include <cmath>

namespace arm {

const char* to_string(Posture posture) {
  switch (posture) {
    case Posture::kStow:
      return "STOW";
    case Posture::kDeploy:
      return "DEPLOY";
    case Posture::kGrip:
      return "GRIP";
  }
  return "UNKNOWN";
}

JointAngles posture_angles(const ArmGeometry& g, Posture posture) {
  switch (posture) {
    case Posture::kStow:
      return g.stow;
    case Posture::kDeploy:
      return g.deploy;
    case Posture::kGrip:
      return g.grip;
  }
  return g.stow;
}

bool within_limits(const ArmGeometry& g, const JointAngles& q) {
  return g.tilt.contains(q.tilt_rad) && g.pan.contains(q.pan_rad);
}

Eigen::Isometry3d forward_kinematics(const ArmGeometry& g, const JointAngles& q) {
  // At zero the link points aft: rotate the frame so its x is body -x.
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translate(g.p_body_base);
  T.rotate(Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitZ()));
  T.rotate(Eigen::AngleAxisd(q.tilt_rad, Eigen::Vector3d::UnitY()));
  T.translate(Eigen::Vector3d(g.proximal_link_m, 0.0, 0.0));
  T.rotate(Eigen::AngleAxisd(q.pan_rad, Eigen::Vector3d::UnitZ()));
  T.translate(Eigen::Vector3d(g.distal_link_m, 0.0, 0.0));
  return T;
}

Eigen::Isometry3d grasp_body_target(const ArmGeometry& g, const Eigen::Isometry3d& T_ref_handrail,
                                    const Eigen::Vector3d& up_ref) {
  const Eigen::Vector3d normal = T_ref_handrail.linear().col(0);
  Eigen::Vector3d along = T_ref_handrail.linear().col(2);
  // In the grip posture the grasp frame's z is the body's z.
  if (along.dot(up_ref) < 0.0) along = -along;
  Eigen::Matrix3d R;
  R.col(0) = -normal;
  R.col(2) = along;
  R.col(1) = along.cross(-normal);
  Eigen::Isometry3d T_ref_grasp = Eigen::Isometry3d::Identity();
  T_ref_grasp.linear() = R;
  T_ref_grasp.translation() = T_ref_handrail.translation();
  return T_ref_grasp * forward_kinematics(g, g.grip).inverse();
}

bool pointing_angles(const ArmGeometry& g, const Eigen::Vector3d& forward_in_grasp,
                     const JointAngles& current, JointAngles* q) {
  const double n = forward_in_grasp.norm();
  if (!(n > 1e-9)) return false;
  const Eigen::Vector3d d = forward_in_grasp / n;
  // From forward_kinematics, the body's x axis seen from the grasp frame is
  // (-cos t cos p, cos t sin p, -sin t): tilt from its z, pan from x and y.
  const double tilt = std::asin(std::clamp(-d.z(), -1.0, 1.0));
  const double pan = std::atan2(d.y(), -d.x());
  // The other solution flips the tilt over the top and turns pan by half a
  // turn.
  const auto wrap = [](double a) { return std::remainder(a, 2.0 * M_PI); };
  const JointAngles candidates[2] = {{tilt, pan}, {wrap(M_PI - tilt), wrap(pan + M_PI)}};
  bool found = false;
  double best = 0.0;
  for (const JointAngles& c : candidates) {
    if (!within_limits(g, c)) continue;
    const double dist =
        std::fabs(c.tilt_rad - current.tilt_rad) + std::fabs(c.pan_rad - current.pan_rad);
    if (!found || dist < best) {
      found = true;
      best = dist;
      *q = c;
    }
  }
  return found;
}

}  // namespace arm
