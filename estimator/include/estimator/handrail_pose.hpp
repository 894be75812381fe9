#pragma once
// Step 4: the handrail frame (eq. 5), the bar's centre line, its end points
// and state, and the robot's target pose.
#include <Eigen/Core>

#include "estimator/config.hpp"
#include "estimator/organized_cloud.hpp"
#include "estimator/pixel_scale.hpp"
#include "estimator/types.hpp"
#include "estimator/workspace.hpp"

namespace estimator {

// The bar's centre line: a point on it and its unit direction, in the
// camera frame, with the direction lying in the wall plane.
struct CenterLine {
  Eigen::Vector3f point = Eigen::Vector3f::Zero();
  Eigen::Vector3f axis = Eigen::Vector3f::Zero();
  float t_min_m = 0.0f;  // visible extent of the inliers along the axis
  float t_max_m = 0.0f;
  float front_height_m = 0.0f;  // the bar's front face, from the wall
  // The mount surface found under the bar (seat_on_mount()): its distance
  // from the dominant plane along the normal.
  float mount_offset_m = 0.0f;
  // Whether that mount is a seat track a step above a surface in view
  // (not a surface itself): a track the bar hides, which past its ends
  // must show (track_past_end.hpp).
  bool on_hidden_track = false;
  // The normal of the surface the bar was verified on (the searched wall's,
  // or the bar's own surface around it): the handrail frame's x axis.
  Eigen::Vector3f wall_normal = Eigen::Vector3f::Zero();
};

// Eq. 5: x = wall normal, z = line direction projected onto the wall,
// y = z x x. The axis sign is fixed so that it points up the image (or right
// for a bar nearer horizontal), which makes results comparable frame to frame.
Eigen::Matrix3f handrail_frame(const Eigen::Vector3f& wall_normal,
                               const Eigen::Vector3f& line_direction);

// Fits the centre line to the line inliers: direction by least squares in
// the wall plane; the bar's front-face height as the mode of the distances
// from the wall of every raised pixel (ws.gap) near the line; position
// across the bar as the middle of the pixels near that front face (placed
// symmetrically about the centre for round and rounded-rectangle bars seen
// from any angle); height from the wall from the configured geometry. Uses
// ws.band and ws.values.
bool estimate_center_line(const OrganizedCloud& cloud, const DetectorConfig& cfg, const Plane& wall,
                          const IndexList& inliers, Workspace& ws, CenterLine* line);

// The bar's front face must stand where the handrail's geometry puts it
// (offset + depth / 2 from the wall, within the tolerance): rejects cables of
// handrail width at other heights.
bool bar_front_height_test(const DetectorConfig& cfg, const CenterLine& line);

// The centre line's axis (the front face's own direction) must run within
// line_max_turn_deg of the candidate line it was estimated from. A line
// that crosses a bar at an angle collects only the patch of the bar under
// it; that patch's front face runs along the bar, and the end walk would
// then find the bar's sides as two ends a few centimetres apart.
bool line_follows_front(const Eigen::Vector3f& candidate_direction, const CenterLine& line,
                        const DetectorConfig& cfg);

// Walks the image past each extreme inlier along the bar. An end is seen
// when the walk leaves the bar and meets the wall; it is not seen when the
// walk leaves the image, meets invalid pixels or something in front.
// end_t_m receives the bar's extent along the axis at seen ends. With
// end_drop_m, each end's drop: how far along the axis raised structure
// (the wall's tolerance or more above the surface the bar is seated on)
// runs on, step by step, past the last pixel at the bar's front height
// (front_level_m, in the distances of ws.signed_distance_m). A handrail's
// front holds to its leg, so its drop is at most the leg's length; a cable
// that reaches a handrail's height comes down to the surface in a ramp,
// whose low part, under the gap window, counts too. Past the inliers, a
// step where the raised ground across the walk is wider than the bar (and,
// seen obliquely, its leg: wall_normal, the normal of the wall the
// distances are measured from, places the leg) is neither the bar nor its
// end: the walk goes on over it without extending the bar.
// The bar's front height along it, a straight line in t (from
// line.point along line.axis): a least-squares fit over the inliers within
// half the bar's depth of the front. A bar's front is straight and
// parallel to the surface under its legs; against a surface fitted around
// it a degree off it slopes by 1.7 cm a metre, and a cable climbing onto a
// box slopes by its climb.
struct FrontAlongBar {
  bool fitted = false;   // false: too few pixels or too short; level_m is the line's front
  float level_m = 0.0f;  // at t = 0
  float slope = 0.0f;    // metres of height per metre along the bar
};
FrontAlongBar fit_front_along_bar(const OrganizedCloud& cloud, const DetectorConfig& cfg,
                                  const Workspace& ws, const IndexList& inliers,
                                  const CenterLine& line);

// front (bar first): the front's height along the bar; the end walk then
// takes the bar's own pixels as those within its depth of that front, and
// "raised" past an end as standing at the bar's own height. Null: the
// level front_level_m and the nominal handrail's window over the wall.
void detect_ends(const OrganizedCloud& cloud, const DetectorConfig& cfg, const PixelScale& scale,
                 const Workspace& ws, const IndexList& inliers, const CenterLine& line,
                 const Eigen::Vector3f& wall_normal, bool end_seen[2], float end_t_m[2],
                 float end_drop_m[2] = nullptr, float front_level_m = 0.0f,
                 const FrontAlongBar* front = nullptr);

// Whether any of the pixels lies within margin_px of the image's border
// (a bar the image's edge cuts).
bool touches_image_border(const OrganizedCloud& cloud, const IndexList& pixels, int margin_px);

// The longest drop an end may show at depth z_m, seen or cut off by the
// image's edge, an occluder or dropouts: the handrail's own
// (end_drop_max_m: its leg's length along the rail) plus two pixels at
// that depth.
float allowed_end_drop_m(const DetectorConfig& cfg, const PixelScale& scale, float z_m);

HandrailState handrail_state(const bool end_seen[2]);

// p_g = p_c + d_c v_P; the target's rotation equals the handrail frame.
void target_pose(const DetectorConfig& cfg, const Eigen::Vector3f& p_cam_center,
                 const Eigen::Matrix3f& R_cam_handrail, Eigen::Vector3f* p_cam_target,
                 Eigen::Matrix3f* R_cam_target);

}  // namespace estimator
