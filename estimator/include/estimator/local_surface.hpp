#pragma once
// The surface a bar's legs stand on, measured around the bar itself. The
// searches measure heights from one plane (the dominant one, or a face
// parallel to it), but on the station a handrail also stands on a corner
// panel at 45 deg to the walls around it, on a block, or on a cupola's
// window frame: there the searched plane says nothing of the bar's height
// or its normal, and the surface around the bar does.
#include "estimator/config.hpp"
#include "estimator/handrail_pose.hpp"
#include "estimator/organized_cloud.hpp"
#include "estimator/random.hpp"
#include "estimator/types.hpp"
#include "estimator/workspace.hpp"

namespace estimator {

struct LocalSurface {
  bool found = false;
  Plane plane;                  // its normal toward the camera
  std::uint32_t inliers = 0;    // of the sampled pixels around the bar
  float front_height_m = 0.0f;  // the bar's pixels' mean distance from it
};

// A plane through the sampled pixels (ws.sample) around the bar: along the
// inliers' extent, 3.5 to 13 cm from their line in 3D (a bar's own faces
// lie within 2 cm of its centre line, the surface under it 5.5 to 10.2 cm
// away), by RANSAC over a few dozen triples and a least-squares refit to
// the pixels within 1 cm. Found when at least 16 pixels and 40 % of those
// around the bar lie on it and the bar's pixels stand a handrail's front
// height in front of it (handrail geometry's range, with 1.5 cm to spare).
// Independent of any wall the search assumed.
LocalSurface fit_surface_around_bar(const OrganizedCloud& cloud, const DetectorConfig& cfg,
                                    const Workspace& ws, const IndexList& inliers,
                                    const Eigen::Vector3f& axis, Random& rng);

// Every valid pixel's distance from `plane` into `distance_m` (-infinity
// where `valid_distance_m` is not finite: the pixel is not valid).
void distances_to_plane(const OrganizedCloud& cloud, const Plane& plane,
                        const float* valid_distance_m, float* distance_m);

// The pixels whose distance in ws.signed_distance_m is that of some
// handrail's visible surface over the plane it was measured from: from the
// back face at the least height to the front at the most (handrail
// geometry's range), widened by gap_margin_m and ws.gap_widen_m (twice the
// pixel's noise). Into `out`, ascending.
void raised_over_surface(const OrganizedCloud& cloud, const DetectorConfig& cfg,
                         const Workspace& ws, IndexList& out);

// The angle between two planes' normals, degrees (0 to 90).
float tilt_between_deg(const Plane& a, const Plane& b);

}  // namespace estimator
