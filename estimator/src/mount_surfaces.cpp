#include "estimator/mount_surfaces.hpp"

#include <cmath>
#include <initializer_list>

#include "estimator/plane_estimation.hpp"

namespace estimator {
namespace {

// The bar's front face is looked for within this of where a mount puts it
// (noise of a few millimetres at the ranges the detector works at).
constexpr float kFrontWindowM = 0.006f;

struct Histogram {
  float lo_m = 0.0f;
  int bins = 0;
  std::uint32_t count[kMountHistogramBins] = {};

  float center_m(int b) const { return lo_m + (static_cast<float>(b) + 0.5f) * kMountBinM; }
  int bin_of(float s_m) const { return static_cast<int>(std::floor((s_m - lo_m) / kMountBinM)); }
  // Bin b's count with its two neighbours'.
  std::uint32_t smoothed(int b) const {
    std::uint32_t n = count[b];
    if (b > 0) n += count[b - 1];
    if (b + 1 < bins) n += count[b + 1];
    return n;
  }
  // Pixels with distances in [lo, hi].
  std::uint32_t sum(float lo, float hi) const { return sum_bins(bin_of(lo), bin_of(hi)); }
  // Pixels in bins b0 to b1, those in the histogram.
  std::uint32_t sum_bins(int b0, int b1) const {
    b0 = b0 < 0 ? 0 : b0;
    b1 = b1 >= bins ? bins - 1 : b1;
    std::uint32_t n = 0;
    for (int b = b0; b <= b1; ++b) n += count[b];
    return n;
  }
};

float bar_front_m(const DetectorConfig& cfg) {
  return cfg.handrail.bar_center_offset_m + 0.5f * cfg.handrail.bar_depth_m;
}

// Every valid pixel's distance from the dominant plane, binned; invalid
// pixels are -infinity and fall below the first bin.
void fill_histogram(const OrganizedCloud& cloud, const DetectorConfig& cfg, const Workspace& ws,
                    Histogram* h) {
  h->lo_m = -(cfg.mount_search_m + kMountBinM * 2.0f);
  const float hi_m = std::fmax(cfg.mount_search_m, cfg.mount_bay_max_m) + cfg.mount_step_m +
                     bar_front_m(cfg) + 0.02f;
  const int bins = static_cast<int>(std::ceil((hi_m - h->lo_m) / kMountBinM));
  h->bins = bins < kMountHistogramBins ? bins : kMountHistogramBins;
  const float* s = ws.signed_distance_m.get();
  const float inv_bin = 1.0f / kMountBinM;
  const float bins_f = static_cast<float>(h->bins);
  const std::size_t n = cloud.size();
  // Every other pixel, counted twice: the surfaces and a bar's front face
  // span many pixels, and this pass is a third of the gap distance pass's
  // cost when it reads them all.
  for (std::size_t i = 0; i < n; i += 2) {
    // -infinity (invalid) and NaN fail; the range is checked before the
    // conversion, which is undefined for a float beyond int's range.
    const float x = (s[i] - h->lo_m) * inv_bin;
    if (!(x >= 0.0f && x < bins_f)) continue;
    h->count[static_cast<int>(x)] += 2;
  }
}

// Whether bin b's smoothed count is more than twice the count a face step
// either side of it (a side past the histogram's end counts as empty).
bool stands_out(const Histogram& h, int b, int step_bins) {
  const std::uint32_t c = h.smoothed(b);
  const bool below = b - step_bins < 0 || 2 * h.smoothed(b - step_bins) < c;
  const bool above = b + step_bins >= h.bins || 2 * h.smoothed(b + step_bins) < c;
  return below && above;
}

// The surfaces: local maxima of the histogram smoothed over three bins,
// within mount_search_m of the plane or where rack faces stand in front of
// an empty bay, with enough pixels. In front of the plane the range runs a
// face step further: faces closer than that merge into one peak under a
// metre's depth noise, at a level between them, so a face at the range's
// end beside one a little further out showed no peak inside it. Behind the
// plane it does not: no mount is searched deeper than mount_search_m
// (handrail_filters.hpp). Each surface lies at the mean of its five bins,
// deepest first (in a bay view the faces lie behind the bars' fronts and
// the clutter's tops, so a full list keeps the faces). A maximum closer
// than a rack's least face step (1 cm) to a better supported one is a tooth
// of the same face: a noisy face seen obliquely breaks into a comb of
// maxima 5 mm apart, which filled the list before the faces behind it were
// reached (a rail's own face among them).
std::uint32_t find_surface_peaks(const Histogram& h, const DetectorConfig& cfg,
                                 std::uint32_t valid_pixels, float peak_m[kMaxSurfacePeaks]) {
  const float min_pixels = cfg.mount_min_fraction * static_cast<float>(valid_pixels);
  // A local maximum has a lower bin after it: at most every other bin.
  constexpr int kMaxMaxima = kMountHistogramBins / 2;
  int maximum_bin[kMaxMaxima];
  int maxima = 0;
  // A rack's least face step, in bins.
  const int step_bins = static_cast<int>(kRackFaceStepM / kMountBinM + 0.5f);
  for (int b = 1; b + 1 < h.bins && maxima < kMaxMaxima; ++b) {
    // Near the plane, or where the rack faces stand in front of a bay.
    const float at_m = h.center_m(b);
    const bool near = at_m >= -cfg.mount_search_m && at_m <= cfg.mount_search_m + kRackFaceStepM;
    const bool bay_front = at_m >= cfg.mount_bay_min_m && at_m <= cfg.mount_bay_max_m;
    if (!near && !bay_front) continue;
    const std::uint32_t c = h.smoothed(b);
    if (static_cast<float>(c) < min_pixels || c < h.smoothed(b - 1) || c <= h.smoothed(b + 1)) {
      continue;
    }
    // Past mount_search_m only a face: it falls to half within a face step
    // either side, as a face's peak is the depth noise wide. A bump on a
    // slope of heights does not: on `clutter-only`'s flat wall one at 5.5
    // to 6 cm, just the 1 % minimum, in almost every frame, cost two more
    // searches a frame.
    if (near && at_m > cfg.mount_search_m && !stands_out(h, b, step_bins)) continue;
    maximum_bin[maxima++] = b;
  }
  // A tooth: a better supported maximum within the step (of two equal, the
  // first in the histogram stays).
  const auto is_tooth = [&](int k) {
    const std::uint32_t c = h.smoothed(maximum_bin[k]);
    for (int j = k - 1; j >= 0 && maximum_bin[k] - maximum_bin[j] < step_bins; --j) {
      if (h.smoothed(maximum_bin[j]) >= c) return true;
    }
    for (int j = k + 1; j < maxima && maximum_bin[j] - maximum_bin[k] < step_bins; ++j) {
      if (h.smoothed(maximum_bin[j]) > c) return true;
    }
    return false;
  };
  std::uint32_t peaks = 0;
  for (int k = 0; k < maxima && peaks < kMaxSurfacePeaks; ++k) {
    if (is_tooth(k)) continue;
    const int b = maximum_bin[k];
    double weighted = 0.0, total = 0.0;
    for (int j = b - 2; j <= b + 2; ++j) {
      if (j < 0 || j >= h.bins) continue;
      weighted += static_cast<double>(h.count[j]) * h.center_m(j);
      total += h.count[j];
    }
    peak_m[peaks++] = static_cast<float>(weighted / total);
  }
  return peaks;
}

// Mounts read off bar-front peaks: a face that holds a handrail may hold
// too few pixels to make a surface peak of its own (a rack's 11 cm frame
// seen obliquely, in the noisy shoulder of the dominant plane's peak), while
// the bar's front over it makes a peak where no surface mount puts one.
// The strongest such peaks (most pixels in the front window), as mounts
// past the surface mounts' capacity, each within the range the surface
// mounts come from (mount_search_m of the plane, plus a seat track's step)
// and none within two histogram resolutions of a mount already there or of
// the plane. The verdict on a line found over one is unchanged: it must
// still be seated on a surface in view or beside it.
void add_front_peak_mounts(const Histogram& h, const DetectorConfig& cfg, float front_m,
                           MountHypotheses* out) {
  const auto explained = [&](float mount_m) {
    if (std::fabs(mount_m) < 2.0f * kSameMountM) return true;
    for (std::uint32_t k = 0; k < out->count; ++k) {
      if (std::fabs(out->offset_m[k] - mount_m) < 2.0f * kSameMountM) return true;
    }
    return false;
  };
  for (std::uint32_t added = 0; added < cfg.front_peak_mounts; ++added) {
    if (out->count >= kMaxMountHypotheses) return;
    float best_m = 0.0f;
    std::uint32_t best_pixels = 0;
    for (int b = 1; b + 1 < h.bins; ++b) {
      const float mount_m = h.center_m(b) - front_m;
      if (mount_m < -cfg.mount_search_m || mount_m > cfg.mount_search_m + cfg.mount_step_m) {
        continue;
      }
      const std::uint32_t c = h.smoothed(b);
      if (c < h.smoothed(b - 1) || c <= h.smoothed(b + 1)) continue;  // not a local maximum
      const std::uint32_t pixels =
          h.sum(mount_m + front_m - kFrontWindowM, mount_m + front_m + kFrontWindowM);
      if (pixels < cfg.min_line_inliers || pixels <= best_pixels || explained(mount_m)) continue;
      best_m = mount_m;
      best_pixels = pixels;
    }
    if (best_pixels == 0) return;
    // The strongest peak may be a face in view (a surface peak) standing
    // at a bar front's height over some mount: that is the face's own
    // peak, not a bar's. Its search would put the whole face in the gap
    // set for the cross test to refuse pixel by pixel; and the weaker peaks
    // behind it are no better supported than the surface mounts already
    // searched (taking the next one instead let more clutter through on
    // the development set), so none is added. What this gives up: a bar
    // whose own front is big enough to make a surface peak, standing on a
    // face too small to make one; neither the development nor the scored
    // set showed one. Demoting the surface mounts whose
    // fronts fall on a face, the same way, lost such bars by the dozen
    // (dev-rack-table2-iss-0-53 100 -> 87 %): close up, the bar's front is
    // a surface peak and its own mount looks like a face's echo.
    bool face_echo = false;
    for (std::uint32_t k = 0; k < out->surface_count; ++k) {
      face_echo |= std::fabs(out->surface_m[k] - (best_m + front_m)) < kFrontWindowM;
    }
    if (face_echo) return;
    out->offset_m[out->count] = best_m;
    out->front_pixels[out->count] = best_pixels;
    out->rank_pixels[out->count] = best_pixels;
    ++out->count;
    ++out->front_peak_count;
  }
}

void add_mount(float offset_m, std::uint32_t front_pixels, std::uint32_t rank_pixels,
               std::uint32_t capacity, MountHypotheses* out) {
  for (std::uint32_t k = 0; k < out->count; ++k) {
    if (std::fabs(out->offset_m[k] - offset_m) < kSameMountM) {
      if (rank_pixels > out->rank_pixels[k]) {
        out->offset_m[k] = offset_m;
        out->front_pixels[k] = front_pixels;
        out->rank_pixels[k] = rank_pixels;
      }
      return;
    }
  }
  // Insert in order of rank, best first; the worst falls off.
  std::uint32_t at = out->count;
  while (at > 0 && out->rank_pixels[at - 1] < rank_pixels) --at;
  if (at >= capacity) return;
  const std::uint32_t last = out->count < capacity ? out->count : capacity - 1;
  for (std::uint32_t k = last; k > at; --k) {
    out->offset_m[k] = out->offset_m[k - 1];
    out->front_pixels[k] = out->front_pixels[k - 1];
    out->rank_pixels[k] = out->rank_pixels[k - 1];
  }
  out->offset_m[at] = offset_m;
  out->front_pixels[at] = front_pixels;
  out->rank_pixels[at] = rank_pixels;
  if (out->count < capacity) ++out->count;
}

}  // namespace

MountHypotheses find_mount_hypotheses(const OrganizedCloud& cloud, const DetectorConfig& cfg,
                                      const Workspace& ws) {
  Histogram h;
  fill_histogram(cloud, cfg, ws, &h);
  std::uint32_t valid = 0;
  for (int b = 0; b < h.bins; ++b) valid += h.count[b];
  float peak_m[kMaxSurfacePeaks];
  const std::uint32_t peaks = find_surface_peaks(h, cfg, valid, peak_m);

  const float front = bar_front_m(cfg);
  const auto front_pixels = [&](float mount_m) {
    return h.sum(mount_m + front - kFrontWindowM, mount_m + front + kFrontWindowM);
  };
  // A surface in the bay's range: the plane is the back of an empty bay.
  bool bay_view = false;
  for (std::uint32_t p = 0; p < peaks; ++p) bay_view |= peak_m[p] >= cfg.mount_bay_min_m;
  // What ranks the mounts. In a bay view seen obliquely the faces in front
  // of the back make a ramp of heights: a mount whose window lies on it
  // collects the ramp's pixels, and five of them outranked a rail's own
  // face, whose window holds the bar's front and little else.
  // There the window's pixels count less those in as wide a window just
  // above it, where nothing of a bar on that mount lies: a ramp gives as
  // many there, a bar's front none. Off a bay the plain count ranks: the
  // same rule there lost more than it won on the development sets (9
  // frames of the first set's dev-rack-table2-iss-mesh-30, raw path, found
  // through the bar-front peak's mount, which the reordered list no longer
  // offered; not traced further; 2 won elsewhere).
  const auto rank_pixels = [&](float mount_m, std::uint32_t in_window) {
    if (!bay_view) return in_window;
    const int b0 = h.bin_of(mount_m + front - kFrontWindowM);
    const int b1 = h.bin_of(mount_m + front + kFrontWindowM);
    const std::uint32_t above = h.sum_bins(b1 + 1, b1 + 1 + (b1 - b0));
    return in_window > above ? in_window - above : 0u;
  };
  const std::uint32_t capacity = bay_view ? cfg.max_mount_hypotheses_bay : cfg.max_mount_hypotheses;
  MountHypotheses out;
  out.dominant_front_pixels = front_pixels(0.0f);
  out.surface_count = peaks;
  for (std::uint32_t p = 0; p < peaks; ++p) out.surface_m[p] = peak_m[p];
  for (std::uint32_t p = 0; p < peaks; ++p) {
    // The bar on the surface itself, or on a seat track standing on it. A
    // mount this near the plane is the plane, which has a search of its
    // own: in the list it took a slot and was never searched, so a view
    // offered one mount fewer than configured.
    for (const float mount : {peak_m[p], peak_m[p] + cfg.mount_step_m}) {
      if (std::fabs(mount) < kSameMountM) continue;
      const std::uint32_t n = front_pixels(mount);
      if (n >= cfg.min_line_inliers) add_mount(mount, n, rank_pixels(mount, n), capacity, &out);
    }
  }
  add_front_peak_mounts(h, cfg, front, &out);
  // Nothing anywhere looks like a bar's front: the dominant plane alone, so
  // that the frame is judged (and its reason given) as on a flat wall.
  if (out.count == 0) {
    const std::uint32_t n = front_pixels(0.0f);
    add_mount(0.0f, n, n, capacity, &out);
  }
  return out;
}

bool find_mount_under_bar(const MountHypotheses& mounts, const DetectorConfig& cfg, float front_m,
                          float tolerance_m, float* mount_m, const float* near_levels,
                          std::uint32_t near_count, bool* on_track_out) {
  const float expected_mount = front_m - bar_front_m(cfg);
  float best_error = tolerance_m;
  bool found = false, on_track = false;
  const auto consider = [&](float mount, bool track) {
    const float error = std::fabs(mount - expected_mount);
    if (error < best_error) {
      best_error = error;
      *mount_m = mount;
      found = true;
      on_track = track;
    }
  };
  consider(0.0f, false);
  for (std::uint32_t k = 0; k < mounts.surface_count && k < kMaxSurfacePeaks; ++k) {
    consider(mounts.surface_m[k], false);
    consider(mounts.surface_m[k] + cfg.mount_step_m, true);
  }
  for (std::uint32_t k = 0; near_levels != nullptr && k < near_count; ++k) {
    consider(near_levels[k], false);
    consider(near_levels[k] + cfg.mount_step_m, true);
  }
  // A bar best explained as standing on the dominant plane's face itself
  // has had its verdict, by the flat-wall rules: it is not found again
  // here. A seat track on a deeper face may top out a few millimetres off
  // that face (faces differ by 1 to 5 cm, the track is 1.3 cm): that is a
  // mount of its own.
  if (on_track_out != nullptr) *on_track_out = found && on_track;
  return found && (on_track || std::fabs(*mount_m) >= kSameMountM);
}

}  // namespace estimator
