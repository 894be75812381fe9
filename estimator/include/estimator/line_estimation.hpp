#pragma once
// Step 3: handrail candidates as two perpendicular lines (Algorithm 2),
// clustering along each line with the cluster distance d_r, and selection by
// the gripper's angle (Algorithm 1).
#include <Eigen/Core>

#include "estimator/config.hpp"
#include "estimator/organized_cloud.hpp"
#include "estimator/random.hpp"
#include "estimator/types.hpp"
#include "estimator/workspace.hpp"

namespace estimator {

struct LineModel {
  bool valid = false;
  Eigen::Vector3f point = Eigen::Vector3f::Zero();
  Eigen::Vector3f direction = Eigen::Vector3f::Zero();  // unit
  float psi_rad = 0.0f;                                 // atan(|dx| / |dy|): 0 along image y
  std::uint32_t score = 0;
};

// The line's angle to the image's y axis, in [0, pi/2].
float line_angle_psi(const Eigen::Vector3f& direction);

// The side set's coordinates in the wall plane (ws.wall_u_m, ws.wall_v_m),
// computed once: the line searches below work on them. Projecting onto the
// wall along its normal also keeps depth noise from blurring the lines.
void project_to_wall(const OrganizedCloud& cloud, const Plane& wall, Workspace& ws);

// Algorithm 2: the two most supported lines among `points` (a subset of the
// side set, after project_to_wall), the weaker one kept near perpendicular
// to the stronger.
void estimate_handrail_candidates(const OrganizedCloud& cloud, const DetectorConfig& cfg,
                                  const Plane& wall, Random& rng, Workspace& ws,
                                  const IndexList& points, LineModel candidates[2]);

// The points within the inlier distance of the line, into out.
void collect_line_inliers(const OrganizedCloud& cloud, const DetectorConfig& cfg, const Plane& wall,
                          const Workspace& ws, const LineModel& line, const IndexList& points,
                          IndexList& out);

// Least-squares refit of a RANSAC line: collects its inliers among
// `points`, fits their principal axis in the wall plane, and repeats, so a
// line from two close samples does not keep their angle error. `inliers`
// holds the final inliers.
void refine_line(const OrganizedCloud& cloud, const DetectorConfig& cfg, const Plane& wall,
                 const Workspace& ws, const IndexList& points, LineModel* line, IndexList& inliers);

// Drops the points within `band_m` of the line that stand no higher above
// the wall than `max_height_m`, so that the next search finds the next line
// (used when a line fails verification: a cable with more support than the
// handrail must not hide it, nor come back as its own remnants).
void remove_line_points(const Plane& wall, const Workspace& ws, const LineModel& line, float band_m,
                        float max_height_m, IndexList& points);

struct Cluster {
  std::uint32_t count = 0;
  float t_min_m = 0.0f;  // along the line, from its point
  float t_max_m = 0.0f;
  float length_m() const { return t_max_m - t_min_m; }
};

// Keeps the most populated run of inliers along the line whose consecutive
// points (in order along it) are closer than d_r; `inliers` is reduced to
// that run, in its previous order. t_scratch[i] gets each point's position.
Cluster cluster_along_line(const OrganizedCloud& cloud, const DetectorConfig& cfg,
                           const LineModel& line, IndexList& inliers, float* t_scratch);

// Algorithm 1, line 10: the candidate closest in angle to the gripper.
// Returns -1 when neither is usable.
int select_by_gripper_angle(const DetectorConfig& cfg, const LineModel candidates[2],
                            const bool usable[2]);

}  // namespace estimator
