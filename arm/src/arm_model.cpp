#include "arm/arm_model.hpp"

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

JointAngles posture_angles(Posture posture) {
  switch (posture) {
    case Posture::kStow:
      return {90.0 * M_PI / 180.0, 0.0};
    case Posture::kDeploy:
      return {0.0, 0.0};
    case Posture::kGrip:
      return {0.0, 0.0};
  }
  return {};
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

}  // namespace arm
