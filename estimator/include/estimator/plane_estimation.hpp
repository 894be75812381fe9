#pragma once
// Step 1: the wall. RANSAC over triples of valid points, scored on a fixed
// subsample, then two least-squares refits on the points within the inlier
// distance (a subsample of a few thousand). The per-pixel distances to the
// wall are computed in the gap distance test's single pass.
#include "estimator/config.hpp"
#include "estimator/organized_cloud.hpp"
#include "estimator/random.hpp"
#include "estimator/types.hpp"
#include "estimator/workspace.hpp"

namespace estimator {

// The least step between neighbouring rack faces (they differ by 1 to 5 cm).
constexpr float kRackFaceStepM = 0.01f;

struct PlaneEstimate {
  bool found = false;
  Plane plane;
  std::uint32_t inliers = 0;  // estimated from the refit's subsample
  // How far apart the outermost faces found along the faces' shared normal
  // lie (plane_faces_normal; 0 when off or none found): a rack's step
  // (1 cm) or more says the view shows rack faces, not one flat wall.
  float faces_span_m = 0.0f;
};

// The wall's input: the usable pixels (valid, within range) of a lattice
// over the frame, at most Workspace::kMaxRefitSamples, into ws.sample and
// ws.refit_*. Returns how many. No pass over every pixel is needed before
// the wall is known; the gap distance test makes the one full pass.
std::size_t sample_valid_points(const OrganizedCloud& cloud, const DetectorConfig& cfg,
                                Workspace& ws);

// Least-squares plane through points (smallest eigenvector of their
// covariance), oriented so that the camera is on its positive side.
bool fit_plane_least_squares(const OrganizedCloud& cloud, const std::int32_t* indices,
                             std::size_t count, Plane* plane);

// Needs sample_valid_points() first.
PlaneEstimate estimate_plane(const OrganizedCloud& cloud, const DetectorConfig& cfg, Random& rng,
                             Workspace& ws);

}  // namespace estimator
