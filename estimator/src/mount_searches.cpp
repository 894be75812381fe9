// The mount searches of the proposed method: the dominant plane and the
// mounts in view, in the order that finds a rack wall's rail soonest, and
// the best find over them.
#include <cmath>

#include "estimator/handrail_detector.hpp"
#include "estimator/handrail_filters.hpp"
#include "estimator/mount_surfaces.hpp"
#include "estimator/pixel_scale.hpp"
#include "estimator/plane_estimation.hpp"

namespace estimator {

// Within 45 deg of the gripper's angle in the image (the paper's psi_p:
// 0 = along image y), from the bar's centre and a point along its axis.
bool HandrailDetector::along_gripper(const HandrailDetection& d) const {
  const Eigen::Vector3f a = d.p_cam_center, b = d.p_cam_center + 0.1f * d.axis();
  if (!(a.z() > 0.0f && b.z() > 0.0f)) return false;
  const float dx = b.x() / b.z() - a.x() / a.z(), dy = b.y() / b.z() - a.y() / a.z();
  const float psi_rad = std::atan2(std::fabs(dx), std::fabs(dy));
  return std::fabs(psi_rad - cfg_.gripper_angle_rad) <= kQuarterPi;
}

// The better of two finds over mounts: along the gripper first, then one
// with an end in view over one with none (its ends passed the leg and ramp
// tests; a find with no end in view may be a rack edge's fin running out of
// the view both ways, which beats a short bar on inliers alone), then more
// line inliers.
bool HandrailDetector::better_find(const HandrailDetection& a, const HandrailDetection& b) const {
  if (b.status != DetectStatus::kFound) return true;
  const bool a_along = along_gripper(a), b_along = along_gripper(b);
  if (a_along != b_along) return a_along;
  const bool a_ends = a.state != HandrailState::kNoEnd, b_ends = b.state != HandrailState::kNoEnd;
  if (a_ends != b_ends) return a_ends;
  return a.inliers > b.inliers;
}

void HandrailDetector::run_proposed(const OrganizedCloud& cloud, std::int64_t start_us,
                                    HandrailDetection* out) {
  scale_ = estimate_pixel_scale(cloud, ws_.sample);
  const PlaneEstimate plane = estimate_plane(cloud, cfg_, rng_, ws_);
  if (!plane.found || !scale_.ok) {
    clear_flags(cloud);
    out->status = DetectStatus::kNoPlane;
    return;
  }
  out->counts.plane_inliers = plane.inliers;
  if (over_budget(start_us)) {
    out->status = DetectStatus::kDeadlineMissed;
    return;
  }

  wall_ = plane.plane;
  dominant_ = plane.plane;
  if (cfg_.bar_first) {
    run_bar_first(cloud, start_us, out);
    return;
  }
  // The distances to the dominant plane, for every pixel, and the mounts
  // they show.
  rack_faces_ = plane.faces_span_m >= kRackFaceStepM;
  out->counts.plane_inliers = gap_distance_test(cloud, cfg_, wall_, ws_, &out->counts.valid);
  keep_plane_pass(cloud, ws_);
  mounts_ = find_mount_hypotheses(cloud, cfg_, ws_);
  out->counts.mount_hypotheses = mounts_.count;

  // The searches: the dominant plane as the mount, exactly as on a flat wall
  // (the front height measured from it alone), and every other mount, best
  // first, with the front height against the surfaces in view. The plane
  // goes first unless another mount shows four times its bar-front pixels
  // (a rack wall, where the flat-wall search mostly fails). A handrail found
  // with at least mount_accept_inliers line inliers ends the search; a
  // weaker one (a fragment, or a far bar) is kept while the others run, and
  // the best (better_find) wins: on a wrong mount the real bar fails the
  // height tests, while a short piece of clutter may pass them. As in
  // Algorithm 1, a find within 45 deg of the gripper's angle beats one
  // across it (a cable crossing the view on the dominant plane must not hide
  // the rail on its seat track), and only such a find ends the search. A
  // frame with none reports what the flat-wall search found (its status and
  // counts).
  constexpr std::uint32_t kDominant = kMaxMountHypotheses;
  std::uint32_t order[kMaxMountHypotheses + 1];
  std::uint32_t searches = 0;
  const bool plane_first =
      mounts_.count == 0 || 4u * mounts_.dominant_front_pixels >= mounts_.front_pixels[0];
  if (plane_first) order[searches++] = kDominant;
  for (std::uint32_t k = 0; k < mounts_.count; ++k) {
    // On the dominant plane a bar whose front stands a seat track higher is
    // found through the mount a step above it.
    if (std::fabs(mounts_.offset_m[k]) >= kSameMountM) order[searches++] = k;
  }
  if (!plane_first) order[searches++] = kDominant;

  HandrailDetection best, flat;
  bool have_flat = false;
  bool dominant_pass_fresh = true;  // the workspace holds the plane's own pass
  std::uint32_t tried = 0, best_slot = kDominant, last_slot = kDominant;
  for (std::uint32_t n = 0; n < searches; ++n) {
    const std::uint32_t slot = order[n];
    // A mount read off a bar-front peak stands in for a face too small to
    // make a surface peak: it is searched only while no mount has held a
    // handrail (it costs a whole search, and a find is already the best
    // of what the surfaces offer).
    const bool front_peak_mount =
        slot != kDominant && slot + mounts_.front_peak_count >= mounts_.count;
    if (front_peak_mount && best.status == DetectStatus::kFound) continue;
    HandrailDetection attempt = *out;
    search_index_ = static_cast<std::uint8_t>(n);
    if (slot == kDominant) {
      strict_mount_ = true;
      search_mount(cloud, plane.plane, kDominant, 0.0f, !dominant_pass_fresh, start_us, &attempt);
      flat = attempt;
      have_flat = true;
    } else {
      strict_mount_ = false;
      search_mount(cloud, plane.plane, slot, mounts_.offset_m[slot], true, start_us, &attempt);
    }
    dominant_pass_fresh = false;
    ++tried;
    last_slot = slot;
    if (n == 0 && !have_flat) flat = attempt;  // reported if the plane is never reached
    if (attempt.status == DetectStatus::kDeadlineMissed) {
      *out = attempt;
      out->counts.mounts_tried = tried;
      return;
    }
    if (attempt.status == DetectStatus::kFound && better_find(attempt, best)) {
      best = attempt;
      best_slot = slot;
      // A bar the plane's search seated beside the plane (see
      // seat_on_mount) does not end the search: the mounts' own searches
      // may find one that stands on what they search. Nor does a find with
      // no end in view: no end of it was put to the leg test, and a fin at
      // a rack's edge running out of the view both ways passes every other
      // test (Columbus); the search goes on, and the best supported find
      // still wins.
      const bool seated_beside = slot == kDominant && attempt.mount_offset_m != 0.0f;
      const bool ends_tested = attempt.state != HandrailState::kNoEnd;
      if (attempt.inliers >= cfg_.mount_accept_inliers && along_gripper(attempt) &&
          !seated_beside && ends_tested) {
        break;
      }
    }
    if (over_budget(start_us)) break;
  }
  if (best.status == DetectStatus::kFound) {
    // The workspace (the debug pictures, the flags) shows the last search;
    // search the winner again if that was another and the pictures need it.
    if (cfg_.workspace_shows_result && best_slot != last_slot) {
      strict_mount_ = best_slot == kDominant;
      HandrailDetection again = *out;
      const bool trace_on = trace_on_;
      trace_on_ = false;  // the same lines again: traced once
      search_mount(cloud, plane.plane, best_slot,
                   strict_mount_ ? 0.0f : mounts_.offset_m[best_slot], true, start_us, &again);
      trace_on_ = trace_on;
    }
    *out = best;
  } else {
    *out = flat;
  }
  out->counts.mounts_tried = tried;
}

}  // namespace estimator
