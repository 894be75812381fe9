#include "estimator/handrail_detector.hpp"

#include <chrono>
#include <cmath>
#include <cstring>
#include <type_traits>

#include "estimator/bar_clearance.hpp"
#include "estimator/bar_profile.hpp"
#include "estimator/bar_runs.hpp"
#include "estimator/handrail_filters.hpp"
#include "estimator/handrail_pose.hpp"
#include "estimator/handrail_types.hpp"
#include "estimator/line_estimation.hpp"
#include "estimator/local_surface.hpp"
#include "estimator/mount_beside.hpp"
#include "estimator/mount_surfaces.hpp"
#include "estimator/plane_estimation.hpp"
#include "estimator/track_past_end.hpp"

namespace estimator {
namespace {
// A bar's pixels this close to the image's border: the edge cuts it.
constexpr int kBorderPx = 3;
// A frame's random stream: the configured seed and the frame id.
std::uint64_t frame_seed(std::uint64_t seed, std::uint64_t frame_id) {
  return seed ^ (frame_id * 0x9e3779b97f4a7c15ull);
}
// The most the pixels' noise widens the front-height test.
constexpr float kMaxNoiseWidening_m = 0.006f;
// Half the least depth step between neighbouring rack faces (1 cm).
constexpr float kSameFaceM = 0.005f;
// What the dominant plane's search seats a bar on besides the plane: only
// the surfaces measured beside it, none of the frame's surface peaks.
const MountHypotheses kNoSurfacesInView{};
}  // namespace

std::int64_t SteadyTimeSource::now_us() const {
  return std::chrono::duration_cast<std::chrono::microseconds>(
             std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

const char* to_string(Method method) {
  return method == Method::kProposed ? "proposed" : "basic";
}

HandrailDetector::HandrailDetector(const DetectorConfig& cfg, const TimeSource* time)
    : cfg_(cfg),
      time_(time ? time : &steady_),
      ws_(static_cast<std::size_t>(cfg.max_width) * cfg.max_height),
      rng_(cfg.seed) {}

bool HandrailDetector::over_budget(std::int64_t start_us) const {
  return cfg_.budget_us > 0 && time_->now_us() - start_us > cfg_.budget_us;
}

// The flags are written afresh by the gap distance test; a frame that stops
// before it must not leave the previous frame's in the debug view.
void HandrailDetector::clear_flags(const OrganizedCloud& cloud) {
  std::memset(ws_.flags.get(), 0, cloud.size());
}

void HandrailDetector::fill_pose(const Eigen::Vector3f& p_cam_center,
                                 const Eigen::Matrix3f& R_cam_handrail,
                                 HandrailDetection* out) const {
  out->status = DetectStatus::kFound;
  out->p_cam_center = p_cam_center;
  out->R_cam_handrail = R_cam_handrail;
  target_pose(cfg_, p_cam_center, R_cam_handrail, &out->p_cam_target, &out->R_cam_target);
}

HandrailDetection HandrailDetector::detect(const OrganizedCloud& cloud, Method method) {
  const std::int64_t start_us = time_->now_us();
  HandrailDetection out;
  out.frame_id = cloud.frame_id;
  out.capture_time_us = cloud.capture_time_us;
  // No earlier frame's surfaces or lines in the diagnostics, whatever this
  // frame's fate.
  mounts_ = MountHypotheses{};
  trace_.clear();
  dominant_ = Plane{};
  if (cloud.width > cfg_.max_width || cloud.height > cfg_.max_height ||
      cloud.size() > ws_.max_pixels) {
    out.status = DetectStatus::kFrameTooLarge;
  } else if (cloud.size() == 0 || cloud.points == nullptr) {
    out.status = DetectStatus::kEmptyFrame;
  } else {
    // Seeded from the frame id: a frame always gives the same answer.
    frame_id_ = cloud.frame_id;
    rng_.reseed(frame_seed(cfg_.seed, cloud.frame_id));
    // Emptiness is judged on the lattice sample: a frame with fewer than
    // three usable pixels in it has no wall to find.
    out.counts.valid = static_cast<std::uint32_t>(sample_valid_points(cloud, cfg_, ws_));
    if (ws_.sample.size() < 3) {
      clear_flags(cloud);
      out.status = DetectStatus::kEmptyFrame;
    } else if (method == Method::kProposed) {
      run_proposed(cloud, start_us, &out);
    } else {
      run_basic(cloud, &out);
    }
  }
  if (out.status == DetectStatus::kFound && over_budget(start_us)) {
    out.status = DetectStatus::kDeadlineMissed;
  }
  if (out.status != DetectStatus::kFound) {
    // No pose may survive into a "not found" result.
    HandrailDetection empty;
    empty.status = out.status;
    empty.frame_id = out.frame_id;
    empty.capture_time_us = out.capture_time_us;
    empty.counts = out.counts;
    out = empty;
  }
  out.processing_time_us = time_->now_us() - start_us;
  return out;
}

// The bar-front-height test, against the surfaces in view rather than the
// one being searched: the search's mount only has to be near enough for the
// bar's pixels to pass the windows of the tests before it, but its front
// face must stand a handrail's height above a surface that is there (or a
// seat track on one). The line is moved onto that mount. The tolerance
// widens with the pixels' noise, since the front face is the mode of noisy
// heights (at 1.2 m the noise is near a centimetre).
bool HandrailDetector::seat_on_mount(const OrganizedCloud& cloud, const IndexList& inliers,
                                     CenterLine* line) const {
  line->on_hidden_track = false;
  if (strict_mount_) {
    line->mount_offset_m = search_mount_m_;
    if (bar_front_height_test(cfg_, *line)) return true;
    // A bar the dominant plane's search found at another height may stand
    // on a face beside the plane (a seat track on a deeper rack face, whose
    // own search never passes the bar's front through the gap window). It
    // is seated only on a surface measured right beside it, not on any
    // surface in view: a cable over the plane has the plane beside it.
  }
  double noise_sum = 0.0;
  for (std::int32_t i : inliers) {
    const float noise = cloud.points[i].noise_m;
    noise_sum += noise > 0.0f && noise < 0.05f ? noise : 0.0f;  // NaN counts 0
  }
  const float mean_noise =
      inliers.empty() ? 0.0f : static_cast<float>(noise_sum / static_cast<double>(inliers.size()));
  const float tolerance =
      cfg_.front_height_tolerance_m + std::fmin(0.5f * mean_noise, kMaxNoiseWidening_m);
  // Beside the plane, the height must tell a face from a seat track on it
  // (a step of 1.3 cm): with the bar's pixels noisier than half the step
  // (past about 1.2 m), its height says nothing of which it stands on.
  if (strict_mount_ && mean_noise > 0.5f * cfg_.mount_step_m) return false;
  const float front_m = line->front_height_m + search_mount_m_;
  float mount_m = 0.0f;
  // The surfaces measured right beside the bar count as surfaces in view:
  // the bar stands on one, or on a seat track on one. Looked for between a
  // track's foot below where the front puts the mount and a little above
  // it (from the search's wall).
  const float expected_mount_m =
      line->front_height_m - (cfg_.handrail.bar_center_offset_m + 0.5f * cfg_.handrail.bar_depth_m);
  const LevelsBeside near = find_levels_beside(
      cloud, cfg_, ws_, wall_, *line, expected_mount_m - cfg_.mount_step_m - 2.0f * tolerance,
      expected_mount_m + 2.0f * tolerance);
  constexpr std::uint32_t kMaxNear = std::extent_v<decltype(LevelsBeside::level_m)>;
  float near_levels[kMaxNear];
  std::uint32_t near_count = 0;
  for (std::uint32_t k = 0; k < near.count && k < kMaxNear; ++k) {
    // Neighbouring faces differ by a centimetre or more: a level nearer
    // the dominant plane than half that is the plane's own face, measured
    // through noise, and a bar on it has had the flat-wall verdict. In the
    // plane's own search the plane's face seats nothing: a bar on a seat
    // track on the plane is for the search of the mount a step above it.
    float level_m = near.level_m[k] + search_mount_m_;
    if (std::fabs(level_m) < kSameFaceM) {
      if (strict_mount_) continue;
      level_m = 0.0f;
    }
    near_levels[near_count++] = level_m;
  }
  const MountHypotheses& in_view = strict_mount_ ? kNoSurfacesInView : mounts_;
  bool on_track = false;
  if (!find_mount_under_bar(in_view, cfg_, front_m, tolerance, &mount_m, near_levels, near_count,
                            &on_track)) {
    return false;
  }
  line->on_hidden_track = on_track;
  line->point += (mount_m - search_mount_m_) * wall_.normal;
  line->front_height_m = front_m - mount_m;
  line->mount_offset_m = mount_m;
  return true;
}

LineVerdict HandrailDetector::verify_candidate(const OrganizedCloud& cloud,
                                               const LineModel& candidate, const IndexList& points,
                                               LineModel* refined, IndexList& inliers,
                                               CenterLine* line, bool ends[2], float end_t[2]) {
  *refined = candidate;
  refine_line(cloud, cfg_, wall_, ws_, points, refined, inliers);
  const Cluster cluster = cluster_along_line(cloud, cfg_, *refined, inliers, ws_.line_t_m.get());
  if (cluster.count < cfg_.min_line_inliers) return LineVerdict::kTooFewPoints;
  if (cfg_.bar_first) {
    // Bar first: every line is judged on the surface around it, whatever
    // the dominant plane is; a line with no surface at a handrail's height
    // behind it is no handrail.
    Random fit_rng(frame_seed(cfg_.seed, frame_id_) ^
                   (0x2545f4914f6cdd1dull * (inliers.size() + 1)));
    const LocalSurface local =
        fit_surface_around_bar(cloud, cfg_, ws_, inliers, refined->direction, fit_rng);
    if (!local.found) return LineVerdict::kWrongHeight;
    const OnLocalSurface on_local(this, cloud, local.plane);
    return verify_on_own_surface(cloud, *refined, inliers, line, ends, end_t);
  }
  if (!estimate_center_line(cloud, cfg_, wall_, inliers, ws_, line)) {
    return LineVerdict::kNoCenterLine;
  }
  const LineVerdict on_wall = verify_on_searched_wall(cloud, *refined, inliers, line, ends, end_t);
  // A bar standing on a surface at an angle to the searched wall (a corner
  // panel, a block's face, a window frame) is judged wrongly against that
  // wall: its height, its mount, its profile, the clearance under it and
  // its ends are all measured from the wrong plane. Refused there, it is
  // verified again, and its pose taken, on the surface around it, where
  // that surface is tilted from the wall (a corner panel stands at 45 deg
  // to the walls beside it; a wall's faces and the fit's noise differ by a
  // few degrees). A line accepted on the wall keeps that verdict and pose
  // (on the rack walls, taking the surface's pose there too moved the
  // errors' 95th percentile from 3.2 to 3.5 mm).
  if (cfg_.own_surface_min_tilt_deg >= 90.0f || on_wall == LineVerdict::kAccepted) {
    return on_wall;
  }
  // Its own random stream, from the frame's and the line's: the line
  // search's draws stay what they would be without this fit.
  Random fit_rng(frame_seed(cfg_.seed, frame_id_) ^ (0x2545f4914f6cdd1dull * (inliers.size() + 1)));
  const LocalSurface local = fit_surface_around_bar(cloud, cfg_, ws_, inliers, line->axis, fit_rng);
  if (!local.found || tilt_between_deg(local.plane, wall_) <= cfg_.own_surface_min_tilt_deg) {
    return on_wall;
  }
  const OnLocalSurface on_local(this, cloud, local.plane);
  return verify_on_own_surface(cloud, *refined, inliers, line, ends, end_t);
}

// The paper's and the mount searches' steps: the front's height over the
// searched wall or a mount in view, then the rest.
LineVerdict HandrailDetector::verify_on_searched_wall(const OrganizedCloud& cloud,
                                                      const LineModel& refined_line,
                                                      const IndexList& inliers, CenterLine* line,
                                                      bool ends[2], float end_t[2]) {
  const LineModel* refined = &refined_line;
  // Algorithm 2 ranks lines by the candidate pixels near them, so a line
  // may cross a bar at an angle and collect the patch under it. That
  // patch's front face runs along the bar, not the line, and the end walk
  // would find the bar's sides as two ends a few centimetres apart: the
  // 0.55 m rail passed as an 8.5 in handrail (in a HIL run). The bar
  // itself is its own family's line.
  if (!line_follows_front(refined->direction, *line, cfg_)) return LineVerdict::kCrossesBar;
  if (!seat_on_mount(cloud, inliers, line)) return LineVerdict::kWrongHeight;
  return verify_seated_line(cloud, inliers, line, ends, end_t, true);
}

// While a bar is verified on its own surface: that surface is the wall
// searched, at mount 0, and the distances are to it; the search's are
// back when this ends.
HandrailDetector::OnLocalSurface::OnLocalSurface(HandrailDetector* d, const OrganizedCloud& cloud,
                                                 const Plane& local)
    : d_(d), wall_(d->wall_), mount_m_(d->search_mount_m_), strict_(d->strict_mount_) {
  Workspace& ws = d->ws_;
  distances_to_plane(cloud, local, ws.signed_distance_m.get(), ws.local_distance_m.get());
  std::swap(ws.signed_distance_m, ws.local_distance_m);
  // The bar's own pixels (the front-face histogram's and the measures'
  // band) are those at a handrail's height over this surface.
  if (d->cfg_.bar_first) raised_over_surface(cloud, d->cfg_, ws, ws.gap);
  d->wall_ = local;
  d->search_mount_m_ = 0.0f;
  d->strict_mount_ = true;
}

HandrailDetector::OnLocalSurface::~OnLocalSurface() {
  std::swap(d_->ws_.signed_distance_m, d_->ws_.local_distance_m);
  d_->wall_ = wall_;
  d_->search_mount_m_ = mount_m_;
  d_->strict_mount_ = strict_;
}

// On the bar's own surface: its front must stand where some handrail's
// legs put it (5.5 to 10.2 cm to the centre line on the station), and the
// centre line lies half the bar's depth behind that front, whatever the
// nominal handrail's height.
LineVerdict HandrailDetector::verify_on_own_surface(const OrganizedCloud& cloud,
                                                    const LineModel& refined,
                                                    const IndexList& inliers, CenterLine* line,
                                                    bool ends[2], float end_t[2]) {
  if (!estimate_center_line(cloud, cfg_, wall_, inliers, ws_, line)) {
    return LineVerdict::kNoCenterLine;
  }
  if (!line_follows_front(refined.direction, *line, cfg_)) return LineVerdict::kCrossesBar;
  const float tolerance = cfg_.front_height_tolerance_m + kMaxNoiseWidening_m;
  if (line->front_height_m < bar_front_min_m(cfg_.handrail) - tolerance ||
      line->front_height_m > bar_front_max_m(cfg_.handrail) + tolerance) {
    return LineVerdict::kWrongHeight;
  }
  line->point += (line->front_height_m - 0.5f * cfg_.handrail.bar_depth_m -
                  cfg_.handrail.bar_center_offset_m) *
                 wall_.normal;
  line->mount_offset_m = 0.0f;
  line->on_hidden_track = false;
  return verify_seated_line(cloud, inliers, line, ends, end_t, false);
}

// The steps after the bar is seated: its mount beside it, the layout's
// track (on a searched wall only), its profile, the clearance under it,
// its ends and its length.
LineVerdict HandrailDetector::verify_seated_line(const OrganizedCloud& cloud,
                                                 const IndexList& inliers, CenterLine* line,
                                                 bool ends[2], float end_t[2],
                                                 bool on_searched_wall) {
  // The mount it was seated on must be there beside it (wall_ is the
  // search's mount plane; the line's mount is measured from the dominant one).
  const MountBeside beside =
      measure_mount_beside(cloud, cfg_, ws_, wall_, *line, line->mount_offset_m - search_mount_m_);
  if (!mount_shows_beside(beside, cfg_)) return LineVerdict::kNoMountBeside;
  // Seated anywhere but on the dominant plane's own face (mount 0, the
  // flat-wall verdict), the bar stands on a rack wall, and there on a seat
  // track.
  const bool off_plane = std::fabs(line->mount_offset_m) > 0.0f;
  if (cfg_.track_beside && on_searched_wall && off_plane && !track_shows_beside(beside, cfg_)) {
    return LineVerdict::kNotOnTrack;
  }
  // On the plane's own face among rack faces, the plane may be a face flush
  // with the track's top: the track shows as a step on one side only. A bar
  // with its mount's level running on at both sides lies over an open face
  // (a cable lying over a face shows it on both sides).
  if (cfg_.track_beside && on_searched_wall && !off_plane && rack_faces_ &&
      open_face_both_sides(beside, cfg_)) {
    return LineVerdict::kNotOnTrack;
  }
  // Seen from its side, a bar shows its side face; a cable only its top.
  if (!profile_fits_bar(measure_bar_profile(ws_, wall_, *line, inliers), cfg_)) {
    return LineVerdict::kShallowProfile;
  }
  // A bar has a grip's clearance under it; a fin or a box edge is solid.
  // Bar first, the band keeps its place under the bar's back face: a bar
  // standing higher than the least a handrail stands has that much more
  // space under it, and a track or strip proud of the surface fitted
  // around it may rise into a band kept over that surface.
  const float band_shift_m =
      cfg_.bar_first ? std::fmax(0.0f, line->front_height_m - bar_front_min_m(cfg_.handrail))
                     : line->mount_offset_m - search_mount_m_;
  const BarClearance clearance =
      measure_bar_clearance(cloud, cfg_, scale_, ws_, *line, inliers, band_shift_m);
  if (!clearance_fits_bar(clearance, cfg_)) return LineVerdict::kSolidBelow;
  float drop_m[2] = {0.0f, 0.0f};
  // The front's height in the search's distances (from its wall, not the
  // mount the line was seated on).
  const float front_level_m = line->front_height_m + line->mount_offset_m - search_mount_m_;
  // Bar first, the end walk follows the front's height along the bar.
  FrontAlongBar front;
  if (cfg_.bar_first) front = fit_front_along_bar(cloud, cfg_, ws_, inliers, *line);
  detect_ends(cloud, cfg_, scale_, ws_, inliers, *line, wall_.normal, ends, end_t, drop_m,
              front_level_m, cfg_.bar_first ? &front : nullptr);
  // Seen or not: an end the image's edge, an occluder or dropouts cut off
  // still shows whatever of it lies in view. A handrail's front holds to
  // its leg up to the cut; a cable coming down a ramp there has left the
  // front's height before it.
  for (int e = 0; e < 2; ++e) {
    const Eigen::Vector3f end_point = line->point + end_t[e] * line->axis;
    if (drop_m[e] > allowed_end_drop_m(cfg_, scale_, end_point.z())) return LineVerdict::kRampEnd;
  }
  // Seated on a track the bar hides, past a seen end that track must
  // stand proud of the face beside it; a cable over a face, read as a bar
  // on a hidden track, has the face running on there.
  // The hidden track's top (the bar's mount) in the heights the measure
  // takes, from the search's wall.
  const float track_top_m = line->mount_offset_m - search_mount_m_;
  if (cfg_.track_beside && line->on_hidden_track &&
      !track_runs_past_end(measure_track_past_end(cloud, scale_, ws_, wall_, *line, end_t), ends,
                           track_top_m, cfg_)) {
    return LineVerdict::kNoTrackPastEnd;
  }
  const Eigen::Vector3f visible_middle = line->point + 0.5f * (end_t[0] + end_t[1]) * line->axis;
  if (visible_middle.norm() > cfg_.max_find_range_m) return LineVerdict::kTooFar;
  // The beam-length check of Algorithm 1 applies in full only when both
  // ends are seen, against every known length; a bar that runs out of view
  // need only be long enough not to be clutter, and never longer than the
  // longest handrail. Below the clutter floor, down to a fraction of the
  // shortest handrail, only where the image's edge cuts the bar: a short
  // piece of clutter in the middle of the view is no partial handrail.
  const float extent = end_t[1] - end_t[0];
  if (ends[0] && ends[1]) {
    return beam_length_matches(cfg_, extent) ? LineVerdict::kAccepted : LineVerdict::kBeamLength;
  }
  if (extent < shortest_partial_bar_m(cfg_)) return LineVerdict::kTooShort;
  if (extent < cfg_.min_visible_length_m && !touches_image_border(cloud, inliers, kBorderPx)) {
    return LineVerdict::kTooShort;
  }
  if (extent > cfg_.beam_length_max_ratio * longest_handrail_m(cfg_)) return LineVerdict::kTooLong;
  return LineVerdict::kAccepted;
}

void HandrailDetector::trace_line(LineVerdict verdict, const IndexList& inliers,
                                  const CenterLine& line, const bool ends[2],
                                  const float end_t[2]) {
  LineTraceEntry e;
  e.search = search_index_;
  e.search_mount_m = search_mount_m_;
  e.verdict = verdict;
  e.inliers = static_cast<std::uint32_t>(inliers.size());
  // How far each line got through verify_candidate's steps, by its verdict.
  e.has_center_line =
      verdict != LineVerdict::kTooFewPoints && verdict != LineVerdict::kNoCenterLine;
  e.seated = e.has_center_line && verdict != LineVerdict::kCrossesBar &&
             verdict != LineVerdict::kWrongHeight;
  e.ends_walked = verdict == LineVerdict::kAccepted || verdict == LineVerdict::kRampEnd ||
                  verdict == LineVerdict::kTooFar || verdict == LineVerdict::kBeamLength ||
                  verdict == LineVerdict::kTooShort || verdict == LineVerdict::kTooLong;
  if (e.has_center_line) {
    // The walked ends bound what is visible; before the walk, the inliers.
    const float t0 = e.ends_walked ? end_t[0] : line.t_min_m;
    const float t1 = e.ends_walked ? end_t[1] : line.t_max_m;
    e.middle_cam = line.point + 0.5f * (t0 + t1) * line.axis;
    e.axis_cam = line.axis;
    e.visible_length_m = t1 - t0;
    e.front_height_m = line.front_height_m;
    e.mount_m = e.seated ? line.mount_offset_m : search_mount_m_;
  }
  if (e.ends_walked) {
    e.end_seen[0] = ends[0];
    e.end_seen[1] = ends[1];
  }
  trace_.push(e);
}

void HandrailDetector::remove_rejected_line(LineVerdict verdict, const LineModel& refined,
                                            const CenterLine& line, IndexList& active) {
  remove_line_points(wall_, ws_, refined, cfg_.line_inlier_m, INFINITY, active);
  // A line whose front stands lower than the bar's is another structure (a
  // pipe, a cable): drop the rest of its width too, or its remnants come
  // back as the next best lines. Only up to its own height: the bar may run
  // right beside it.
  const HandrailGeometry& h = cfg_.handrail;
  const float expected_front = h.bar_center_offset_m + 0.5f * h.bar_depth_m;
  if (verdict == LineVerdict::kWrongHeight && line.front_height_m < expected_front) {
    const float half_width_max =
        0.5f * cfg_.side_width_max_ratio * std::fmax(h.bar_width_m, h.bar_depth_m);
    remove_line_points(wall_, ws_, refined, half_width_max,
                       line.front_height_m + cfg_.front_height_tolerance_m, active);
  }
}

void HandrailDetector::search_mount(const OrganizedCloud& cloud, const Plane& dominant,
                                    std::uint32_t slot, float offset_m, bool run_gap_pass,
                                    std::int64_t start_us, HandrailDetection* out) {
  rng_.reseed(frame_seed(cfg_.seed, cloud.frame_id) ^ ((slot + 1ull) * 0xbf58476d1ce4e5b9ull));
  out->mount_offset_m = offset_m;
  search_mount_m_ = offset_m;
  wall_ = dominant;
  wall_.d -= offset_m;
  // Again where a face is wall: the plane's first pass ran before the faces were known.
  const std::uint32_t faces = cfg_.cross_faces_wall ? mounts_.surface_count : 0;
  if (run_gap_pass || faces_beside_mount(cfg_, offset_m, mounts_.surface_m, faces)) {
    gap_distance_shifted(cloud, cfg_, offset_m, ws_, &out->counts.valid, mounts_.surface_m, faces);
  }
  search_on_mount(cloud, start_us, out);
}

void HandrailDetector::search_on_mount(const OrganizedCloud& cloud, std::int64_t start_us,
                                       HandrailDetection* out) {
  cross_point_test(cloud, cfg_, wall_, scale_, ws_);
  // The dominant plane's search seats a bar beside the plane (seat_on_mount),
  // so its candidates may stand on a deeper face.
  side_width_test(cloud, cfg_, scale_, ws_,
                  strict_mount_ ? FrontFace::kOnSearchedOrDeeper : FrontFace::kOnSearchedSurface);
  out->counts.gap = static_cast<std::uint32_t>(ws_.gap.size());
  out->counts.cross = static_cast<std::uint32_t>(ws_.cross.size());
  out->counts.side = static_cast<std::uint32_t>(ws_.side.size());
  search_lines(cloud, start_us, out);
}

void HandrailDetector::search_lines(const OrganizedCloud& cloud, std::int64_t start_us,
                                    HandrailDetection* out) {
  if (ws_.side.size() < cfg_.min_line_inliers) {
    out->status = DetectStatus::kNoCandidates;
    return;
  }
  if (over_budget(start_us)) {
    out->status = DetectStatus::kDeadlineMissed;
    return;
  }

  // Algorithm 2, repeated: a slot's best line that fails verification is
  // removed and the search runs again on what is left, a bounded number
  // of times.
  project_to_wall(cloud, wall_, ws_);
  IndexList& active = ws_.scratch;
  active.clear();
  for (std::int32_t i : ws_.side) active.push(i);
  LineModel chosen_line[2];
  bool usable[2] = {false, false};
  CenterLine lines[2];
  bool ends[2][2] = {};
  float end_t[2][2] = {};
  for (std::uint32_t attempt = 0; attempt < cfg_.line_attempts; ++attempt) {
    LineModel candidates[2];
    estimate_handrail_candidates(cloud, cfg_, wall_, rng_, ws_, active, candidates);
    ++out->counts.line_searches;
    bool removed = false;
    for (const LineModel& candidate : candidates) {
      if (!candidate.valid) continue;
      // Each search assigns its two slots afresh, so match the candidate to
      // an angle family by its angle: a family that already has an accepted
      // line needs no other.
      bool family_done = false;
      for (int k = 0; k < 2; ++k) {
        family_done |=
            usable[k] && std::fabs(candidate.psi_rad - chosen_line[k].psi_rad) < kQuarterPi;
      }
      if (family_done) continue;
      const int k = usable[0] ? 1 : 0;
      LineModel refined;
      const LineVerdict verdict = verify_candidate(cloud, candidate, active, &refined, ws_.line[k],
                                                   &lines[k], ends[k], end_t[k]);
      if (trace_on_) trace_line(verdict, ws_.line[k], lines[k], ends[k], end_t[k]);
      if (attempt == 0 && out->counts.first_rejection == LineVerdict::kAccepted) {
        out->counts.first_rejection = verdict;
      }
      if (verdict == LineVerdict::kAccepted) {
        usable[k] = true;
        chosen_line[k] = candidate;
        if (usable[0] && usable[1]) break;
      } else {
        remove_rejected_line(verdict, refined, lines[k], active);
        removed = true;
      }
    }
    // The slots are near perpendicular, so an accepted line within 45 deg
    // of the gripper angle wins Algorithm 1's selection whatever the other
    // slot would find: no need to keep searching for it.
    bool settled = usable[0] && usable[1];
    for (int k = 0; k < 2; ++k) {
      settled |=
          usable[k] && std::fabs(chosen_line[k].psi_rad - cfg_.gripper_angle_rad) <= kQuarterPi;
    }
    if (settled || !removed || active.size() < cfg_.min_line_inliers || over_budget(start_us)) {
      break;
    }
  }
  const int chosen = select_by_gripper_angle(cfg_, chosen_line, usable);
  if (chosen < 0) {
    out->status = DetectStatus::kNoLine;
    return;
  }
  const CenterLine& line = lines[chosen];
  out->mount_offset_m = line.mount_offset_m;
  const IndexList& inliers = ws_.line[chosen];
  for (std::int32_t i : inliers) ws_.flags[i] |= kFlagLine;
  out->counts.line = static_cast<std::uint32_t>(inliers.size());
  out->inliers = out->counts.line;

  const Eigen::Matrix3f R = handrail_frame(line.wall_normal, line.axis);
  for (int e = 0; e < 2; ++e) {
    out->end_seen[e] = ends[chosen][e];
    out->ends_cam[e] = line.point + end_t[chosen][e] * line.axis;
  }
  out->state = handrail_state(out->end_seen);
  out->visible_length_m = end_t[chosen][1] - end_t[chosen][0];
  out->beam_length_m = out->state == HandrailState::kBothEnds ? out->visible_length_m : 0.0f;
  if (out->state == HandrailState::kBothEnds) {
    out->handrail_type = match_handrail_type(cfg_, out->beam_length_m);
    if (out->handrail_type >= 0) {
      const HandrailType& type = cfg_.handrail_types[out->handrail_type];
      out->handrail_type_name = type.name;
      out->length_m = type.bar_length_m;
    }
  }
  // Both ends seen: the centre is midway between them. Otherwise the middle
  // of what is visible (the paper's Tr2); the tracker refines it over frames.
  const float t_center = 0.5f * (end_t[chosen][0] + end_t[chosen][1]);
  fill_pose(line.point + t_center * line.axis, R, out);
}

void HandrailDetector::run_bar_first(const OrganizedCloud& cloud, std::int64_t start_us,
                                     HandrailDetection* out) {
  // The distances to the dominant plane: the heights the bar runs are
  // measured in, and the plane the lines are searched in.
  search_mount_m_ = 0.0f;
  strict_mount_ = true;
  search_index_ = 0;
  out->mount_offset_m = 0.0f;
  out->counts.plane_inliers = gap_distance_test(cloud, cfg_, wall_, ws_, &out->counts.valid);
  find_bar_runs(cloud, cfg_, scale_, ws_);
  out->counts.side = static_cast<std::uint32_t>(ws_.side.size());
  out->counts.mounts_tried = 1;
  rng_.reseed(frame_seed(cfg_.seed, cloud.frame_id) ^ 0xbf58476d1ce4e5b9ull);
  search_lines(cloud, start_us, out);
}

}  // namespace estimator
