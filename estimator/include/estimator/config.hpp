#pragma once
// Handrail geometry and detector thresholds. Every number the detector uses
// lives here; the defaults are documented in estimator/doc/config.md.
#include <cstdint>

namespace estimator {

// Geometry of the bar, in the handrail frame: x = wall normal, z = along the
// bar. Two kinds ship: the paper's round model and the real ISS bar.
struct HandrailGeometry {
  float bar_width_m;          // across the bar, parallel to the wall
  float bar_depth_m;          // along the wall normal
  float bar_center_offset_m;  // centre line's distance from the wall, nominal
  float bar_length_m;         // between the centre-line end points
  // The least and the most the centre line stands off the surface its legs
  // stand on, over every handrail of this kind (0: the nominal alone).
  float bar_center_offset_min_m = 0.0f;
  float bar_center_offset_max_m = 0.0f;
};

// The paper's model: round bar 3.5 cm across on 6.5 cm legs.
HandrailGeometry paper_round_handrail(float bar_length_m = 0.55f);
// The ISS bar: rounded rectangle 3.5 cm deep by 1.9 cm across, centre line
// 6.1 cm off the wall on a catalogue handrail; 5.5 to 10.2 cm over the
// surface under its legs across the station's modules (on seat tracks, flat
// panels, 45 deg corner panels, blocks).
HandrailGeometry iss_handrail(float bar_length_m = 0.55f);

// The bar's front face over the surface its legs stand on: the least and
// the most the geometry allows.
float bar_front_min_m(const HandrailGeometry& h);
float bar_front_max_m(const HandrailGeometry& h);

// A handrail length the detector knows: a bar seen end to end is matched to
// the nearest one (the beam-length check of Algorithm 1, per length).
struct HandrailType {
  const char* name;  // static storage: "8.5 in", "module rail", ...
  float bar_length_m;
};
constexpr std::uint32_t kMaxHandrailTypes = 8;
constexpr std::uint32_t kMaxMountHypotheses = 6;

struct DetectorConfig {
  HandrailGeometry handrail = iss_handrail();
  // The lengths accepted when both ends are seen. None (count 0): the one
  // length handrail.bar_length_m. The default: the station's four ISS
  // handrails (bars 0.20, 0.53, 0.76, 1.04 m) and the 1 m module rail.
  HandrailType handrail_types[kMaxHandrailTypes] = {{"8.5 in", 0.202f},
                                                    {"21.5 in", 0.531f},
                                                    {"30 in", 0.762f},
                                                    {"41.5 in", 1.040f},
                                                    {"module rail", 1.000f}};
  std::uint32_t handrail_type_count = 5;

  // Input gating.
  float min_range_m = 0.10f;
  float max_range_m = 2.00f;
  // A handrail is reported only where its checks can tell it from what
  // looks like it: a line whose visible middle lies farther than this is
  // refused (TOO_FAR). Past 1.5 m the bar (1.9 cm) is under three pixels
  // across and its pixels' depth noise (about 1 % of range, 7 mm and more)
  // is half the seat track's 1.3 cm step, so its height, side width,
  // profile and clearance no longer separate it from a rack's edge or a
  // cable. Points out to max_range_m still feed the wall and mount
  // estimates. The flown detector cut all points at 1.5 m.
  float max_find_range_m = 1.50f;

  // Plane estimation (RANSAC over 3 points, then least squares on inliers).
  // RANSAC draws at least plane_iterations hypotheses, and goes on (up to
  // plane_max_iterations) until, at the best hypothesis's inlier share w,
  // 99 % of runs would have drawn one all-inlier triple: 1 - (1 - w^3)^n.
  // On a flat wall w is 0.6 or more and 40 suffice; on a rack wall the
  // largest face may hold a quarter of the view, where 40 draws miss it
  // one time in three.
  std::uint32_t plane_iterations = 40;
  std::uint32_t plane_max_iterations = 300;
  std::uint32_t plane_score_samples = 800;  // points scored per hypothesis
  float plane_inlier_m = 0.015f;
  float plane_min_inlier_fraction = 0.20f;
  // Last, the normal the faces of a rack wall share, from cells of the view
  // that lie on one face and a fit over each face about its own centroid
  // (plane_estimation.cpp). On rack walls the broad plane tilts 1 to 2 deg
  // (median) between faces a centimetre apart, up to 5 to 13 deg; this
  // takes the development set's median under 0.4 deg. Applied only where
  // faces a centimetre or more apart show (a flat wall keeps its broad
  // fit). With the wall right, more handrail-like cables pass the height
  // test (development set: 56 -> 81 false frames without a handrail),
  // which the seat-track test below (track_beside) refuses.
  bool plane_faces_normal = true;

  // Mount surfaces. The surface a handrail stands on need not be the
  // dominant plane: on a rack wall it is a seat track (1.3 cm proud of its
  // rack's face) between faces 1 to 5 cm apart. The faces are parallel, so
  // the surfaces in view are the peaks of a histogram of distances along
  // the dominant plane's normal; each peak within mount_search_m of the
  // plane is a mount, and so is a seat track mount_step_m above it. In
  // front of the plane a peak up to a face step (1 cm) further out is one
  // too, if it stands out as a face's does: two faces that close merge
  // into one peak under the depth noise, at a level between them. Mounts
  // are tried best first (the most pixels where that mount puts the bar's
  // front face), at most max_mount_hypotheses, until one holds a handrail.
  float mount_search_m = 0.052f;
  // Surfaces this far in front of the dominant plane are mounts too: the
  // plane may be the back of an empty rack bay (about 35 cm deep), with the
  // rack faces, and the handrail, standing in front of it. Nearer than the
  // first figure are boxes (5 to 20 cm proud), which are not mounts.
  float mount_bay_min_m = 0.25f;
  float mount_bay_max_m = 0.45f;
  float mount_step_m = 0.013f;
  float mount_min_fraction = 0.01f;  // of the valid pixels, for a surface peak
  std::uint32_t max_mount_hypotheses = 3;
  // In a view of an empty bay (a surface peak in the bay's range) the
  // faces in front of the back each offer a mount and a track on it, and a
  // face standing a bar front's height over another face gives that one's
  // mount the most front pixels: the ranking is no guide there, so more of
  // them are searched. At least max_mount_hypotheses.
  std::uint32_t max_mount_hypotheses_bay = 5;
  // Mounts read off the bar's front instead (mount_surfaces.hpp): the
  // strongest peaks of the histogram where a bar's front face could stand
  // over a mount no surface peak offers, searched after those and only
  // while none of them has held a handrail. At most kMaxMountHypotheses
  // less the larger of max_mount_hypotheses and max_mount_hypotheses_bay.
  std::uint32_t front_peak_mounts = 1;
  // A handrail found with this many line inliers ends the search over
  // mounts; with fewer, the other mounts are searched too.
  std::uint32_t mount_accept_inliers = 120;
  // The mount beside the bar (mount_beside.hpp): in a band from
  // mount_beside_min_m (past a seat track's half width, 1.3 cm) to
  // mount_beside_max_m across from the centre line, at least
  // mount_beside_min_fraction of one side's sampled pixels lie on the
  // mount, or on the face a seat track stands on, within the tolerance
  // (widened by twice the pixel's noise). A side with fewer than
  // mount_beside_min_pixels sampled pixels is not judged.
  float mount_beside_min_m = 0.015f;
  float mount_beside_max_m = 0.06f;
  float mount_beside_tolerance_m = 0.005f;
  float mount_beside_min_fraction = 0.3f;
  std::uint32_t mount_beside_min_pixels = 4;
  // A bar seated on a face other than the dominant plane stands on a rack
  // wall, where handrails stand on seat tracks: past the track's half width
  // the view shows the face a track step below its mount, or a gap, not
  // its mount's own level running on (mount_beside.hpp, NOT_ON_TRACK).
  // With plane_faces_normal (on its own it refuses real rails on close
  // approaches, where the broad plane tilts across faces and the levels
  // beside the bar come out wrong): development set's false frames without
  // a handrail 52 -> 18 of 268. A side
  // showing the track's foot lets a bar pass whose other side shows the
  // mount's level (a neighbouring face flush with the track's top). It also
  // refuses a bar seated on the dominant plane's own face where the view
  // shows rack faces a step apart and both sides of the bar show the
  // mount's level (open_face_both_sides): 8 -> 2 of 204 on the development
  // set's rack walls; and a bar seated on a seat track its width hides
  // whose seen end shows no track past it (track_past_end.hpp).
  bool track_beside = true;
  // A side of the band judged for it needs this many sampled pixels: the
  // side behind a bar seen obliquely shows a sliver (3 to 7 sampled pixels
  // behind the 0.55 m rail seen 25 to 30 deg from its side), too few to say
  // what level runs there.
  std::uint32_t track_beside_min_pixels = 10;

  // Gap distance test (eq. 1): the bar's visible surface lies between
  // offset - depth/2 and offset + depth/2 from the wall, widened by this
  // margin plus twice the pixel's noise.
  float gap_margin_m = 0.008f;

  // Cross point test (eqs. 2, 3). d_c = sqrt(2) b_D + delta.
  float cross_delta_m = 0.035f;
  float wall_tolerance_m = 0.02f;  // d_g,min: "on the wall" (or anywhere below it)
  // ... and on a surface in view (a face of the frame's height histogram)
  // standing between that and the gap window over the search's mount: the
  // face beside a seat track on a rack (gap_distance_shifted).
  bool cross_faces_wall = true;

  // Side width test (eq. 4) on the raised span through the pixel.
  float side_width_min_ratio = 0.6f;  // x bar width
  float side_width_max_ratio = 1.6f;  // x max(bar width, bar depth)
  // ... and the run's highest point must be the bar's front face, within
  // this plus twice the pixel's noise.
  float run_peak_tolerance_m = 0.012f;

  // Handrail candidates (Algorithm 2) and clustering (Algorithm 1).
  std::uint32_t line_iterations = 80;
  std::uint32_t line_score_samples = 600;
  std::uint32_t line_attempts = 6;  // searches after rejected lines
  float line_inlier_m = 0.015f;
  float cluster_gap_m = 0.05f;  // d_r
  // The most the front face's own direction (estimate_center_line) may
  // turn from the line the candidates gave: a line crossing a bar at an
  // angle collects a short patch of it, whose front face runs along the
  // bar, not along the line (CROSSES_BAR).
  float line_max_turn_deg = 20.0f;
  float beam_length_min_ratio = 0.75f;  // b_H,min / b_H when both ends seen
  float beam_length_max_ratio = 1.25f;  // b_H,max / b_H
  float min_visible_length_m = 0.08f;   // shorter segments are clutter
  // Where the image's edge cuts a bar, down to this fraction of the
  // shortest known handrail instead: a bar 35 % in view is one the robot
  // must find, and 35 % of the station's 0.20 m bar is 7 cm
  // (shortest_partial_bar_m, verify_candidate).
  float min_visible_fraction = 0.35f;
  float front_height_tolerance_m = 0.004f;  // bar front face vs geometry
  // A surface around a candidate bar tilted more than this from the
  // searched wall is the bar's own (a corner panel, a block, a window
  // frame): the bar is verified, and its pose taken, on it, against the
  // handrail geometry's range of heights (local_surface.hpp). 90: never.
  float own_surface_min_tilt_deg = 15.0f;
  // Bar first (bar_runs.hpp): candidates from the bar's own runs, with no
  // wall window and no mount search, and every line verified on the
  // surface around it. Off: the paper's tests on the dominant plane and
  // the mounts in view.
  bool bar_first = false;
  // The bar's profile (bar_profile.hpp): seen at least this far from
  // face-on across the bar, the line's inliers must spread at least this
  // far in height above the wall (10th to 90th percentile). The ISS bar's
  // side face then shows down to its back, 3.5 cm below its front; a round
  // cable shows at most its radius (1.25 cm for the thickest).
  float profile_min_obliquity_deg = 20.0f;
  float profile_min_spread_m = 0.017f;
  // The clearance under the bar (bar_clearance.hpp): the band of heights
  // above the line's mount where a grip's space is, and the share of one
  // side's inlier walks that may meet a side face reaching into it.
  float clearance_low_m = 0.012f;
  float clearance_high_m = 0.030f;
  float clearance_max_solid_fraction = 0.3f;
  std::uint32_t min_line_inliers = 25;

  // Selection by the gripper's angle psi_p: 0 = handrails along image y.
  float gripper_angle_rad = 0.0f;

  // End detection: how far past the bar's last pixel to look for the wall.
  float end_search_m = 0.10f;
  // A seen end's drop (detect_ends): how far raised structure (2 cm or
  // more above the surface the bar is seated on) runs on, unbroken, past
  // the last pixel at the bar's front height. At a handrail's end the only
  // such structure is its leg, about 4.5 cm along the rail (the ISS meshes),
  // and seen from the side the leg's face shows below the front over that
  // length; a cable at a handrail's height comes down to the surface in a
  // ramp. Past this plus two pixels, the end is no handrail's.
  float end_drop_max_m = 0.045f;

  // Target pose: p_g = p_c + d_c v_P.
  float target_standoff_m = 0.35f;

  // Random numbers are seeded per frame from this and the frame id, so a
  // frame gives the same answer whenever it is processed.
  std::uint64_t seed = 0x5eed2024u;

  // Largest frame the detector is sized for.
  std::uint32_t max_width = 224;
  std::uint32_t max_height = 171;

  // For debug pictures: when the winning search over mounts was not the
  // last one, search it again so that the workspace's flags show it (a
  // whole extra search on such frames; off in flight).
  bool workspace_shows_result = false;

  // Per-frame budget; 0 = no budget.
  std::int64_t budget_us = 0;
};

// Derived thresholds (one place, so tests and tools agree).
float gap_min_m(const DetectorConfig& cfg);
float gap_max_m(const DetectorConfig& cfg);
float cross_distance_m(const DetectorConfig& cfg);  // d_c

// Checks ranges and relations; returns nullptr when valid, otherwise the
// name of the first offending field.
const char* validate(const DetectorConfig& cfg);

}  // namespace estimator
