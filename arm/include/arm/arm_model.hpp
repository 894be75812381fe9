#pragma once
// The perching arm: a proximal (tilt) joint, a distal (pan) joint and the
// gripper, mounted on the robot's aft face. Geometry comes from ArmGeometry;
// the defaults describe the 24 cm prototype arm.
//
// Body frame: x forward, y left, z up. The arm is mounted at `p_body_base`
// pointing aft (-x) when both joints are at zero. Tilt turns about the
// body's y axis; pan then turns about the tilted link's z axis.
#include <Eigen/Geometry>

namespace arm {

struct JointLimits {
  double min_rad, max_rad;
  bool contains(double q) const { return q >= min_rad && q <= max_rad; }
};

struct JointAngles {
  double tilt_rad = 0.0;
  double pan_rad = 0.0;
};

struct ArmGeometry {
  Eigen::Vector3d p_body_base = Eigen::Vector3d(-0.16, 0.0, -0.05);  // tilt joint, m
  double proximal_link_m = 0.10;                                     // tilt axis to pan axis
  double distal_link_m = 0.14;  // pan axis to the gripper's grasp point
  JointLimits tilt{-120.0 * M_PI / 180.0, 90.0 * M_PI / 180.0};
  JointLimits pan{-90.0 * M_PI / 180.0, 90.0 * M_PI / 180.0};
  // Postures. Stowed folds the arm against the body; deployed holds the
  // link straight aft; grip is deployed with the gripper square to the
  // wall, so that once perched the link stands normal to the wall.
  JointAngles stow{90.0 * M_PI / 180.0, 0.0};
  JointAngles deploy{0.0, 0.0};
  JointAngles grip{0.0, 0.0};
};

enum class Posture { kStow, kDeploy, kGrip };
const char* to_string(Posture posture);
JointAngles posture_angles(const ArmGeometry& g, Posture posture);

bool within_limits(const ArmGeometry& g, const JointAngles& q);

// The gripper's grasp frame in the body frame: origin at the grasp point,
// x along the distal link (outward), z along the pan axis.
Eigen::Isometry3d forward_kinematics(const ArmGeometry& g, const JointAngles& q);

// Where the body must be for the gripper, in the grip posture, to hold a
// handrail: the grasp point on the bar's centre line, the link along the
// wall normal into the wall, the fingers closing across the bar. The
// handrail frame is the estimator's (x = wall normal toward the robot, z
// along the bar), given in any reference frame; of the two ways round the
// bar, the one whose body z is nearer `up_ref` (the robot's present up).
Eigen::Isometry3d grasp_body_target(const ArmGeometry& g, const Eigen::Isometry3d& T_ref_handrail,
                                    const Eigen::Vector3d& up_ref);

// Perched, the gripper is fixed to the handrail and the joints turn the
// body about it. Given the direction in which the body's x axis (its
// forward cameras) should point, expressed in the grasp frame, finds the
// joint angles within limits that give it; of the two solutions, the one
// nearer `current`. Returns false when neither is within limits or the
// direction is zero.
bool pointing_angles(const ArmGeometry& g, const Eigen::Vector3d& forward_in_grasp,
                     const JointAngles& current, JointAngles* q);

}  // namespace arm
