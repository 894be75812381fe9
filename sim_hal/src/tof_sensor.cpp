#include "sim_hal/tof_sensor.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "sim_hal/sim_random.hpp"

namespace sim_hal {

float flying_pixel_threshold_m(float range_m) {
  return std::min(0.14f, std::max(0.018f, 0.018f + (range_m - 1.0f) * (0.122f / 3.5f)));
}

namespace {

constexpr int kTile = 8;

// GCC's portable 128-bit vectors (SSE2 here; the simulator is host only).
typedef float Floats4 __attribute__((vector_size(16)));
typedef std::int32_t Ints4 __attribute__((vector_size(16)));

Floats4 load_floats4(const float* p) {
  Floats4 v;
  std::memcpy(&v, p, sizeof v);
  return v;
}

}  // namespace

DepthRenderer::DepthRenderer(const CameraIntrinsics& cam, const ToFSettings& settings)
    : cam_(cam), settings_(settings), rays_(pixel_rays(cam)) {
  // Each tile's extent in normalised image coordinates.
  const int w = static_cast<int>(cam.width), h = static_cast<int>(cam.height);
  for (int ty = 0; ty < h; ty += kTile) {
    for (int tx = 0; tx < w; tx += kTile) {
      TileBounds b{INFINITY, -INFINITY, INFINITY, -INFINITY};
      for (int y = ty; y < std::min(h, ty + kTile); ++y) {
        for (int x = tx; x < std::min(w, tx + kTile); ++x) {
          const Eigen::Vector3f& r = rays_[static_cast<std::size_t>(y * w + x)];
          b.x_min = std::min(b.x_min, r.x() / r.z());
          b.x_max = std::max(b.x_max, r.x() / r.z());
          b.y_min = std::min(b.y_min, r.y() / r.z());
          b.y_max = std::max(b.y_max, r.y() / r.z());
        }
      }
      tile_bounds_.push_back(b);
    }
  }
  tile_begin_.resize(tile_bounds_.size() + 1);
  const std::size_t n = rays_.size();
  range_.resize(n);
  measured_.resize(n);
  amplitude_.resize(n);
  cos_incidence_.resize(n);
  bias_.resize(n);
  surface_.resize(n);
  point_z_.resize(n);
  noise_draw_.resize(n);
  flying_candidate_.resize(n);
  sorted_.reserve(n);
  // A pixel whose multipath window lies inside the image has (win + 1)^2
  // samples; its bias is one of that many + 1 values, worked out once.
  const int win = settings.multipath_window_px, full = (win + 1) * (win + 1);
  for (int k = 0; k <= full; ++k) {
    bias_for_count_.push_back(static_cast<float>(settings.multipath_gain_m * k / full));
  }
}

// Whether any point of a tile lies within the segment image's margin of
// its segment: the distance from the tile's centre to the segment against
// the margin plus the tile's half diagonal.
bool DepthRenderer::segment_near_tile(const SegmentImage& seg, const TileBounds& tile) {
  const float cx = 0.5f * (tile.x_min + tile.x_max), cy = 0.5f * (tile.y_min + tile.y_max);
  const float half_diag = 0.5f * std::hypot(tile.x_max - tile.x_min, tile.y_max - tile.y_min);
  const float ex = seg.x1 - seg.x0, ey = seg.y1 - seg.y0;
  const float len2 = ex * ex + ey * ey;
  float along = len2 > 0.0f ? ((cx - seg.x0) * ex + (cy - seg.y0) * ey) / len2 : 0.0f;
  along = std::clamp(along, 0.0f, 1.0f);
  const float dx = cx - (seg.x0 + along * ex), dy = cy - (seg.y0 + along * ey);
  const float reach = seg.margin + half_diag;
  return dx * dx + dy * dy <= reach * reach;
}

void DepthRenderer::cull_surfaces_per_tile(const Scene& scene,
                                           const Eigen::Isometry3d& T_world_cam) {
  const Eigen::Isometry3d T_cam_world = T_world_cam.inverse();
  // Each surface's extent in normalised image coordinates: the pinhole
  // image of a convex hull is the hull of its points' images, widened by
  // the hull's radius at its nearest depth. A hull reaching behind the
  // image plane could cover any direction: every tile keeps it.
  surface_bounds_.clear();
  surface_segments_.clear();
  for (const Surface& s : scene.surfaces) {
    SegmentImage seg{false, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f};
    TileBounds b{INFINITY, -INFINITY, INFINITY, -INFINITY};
    double z_min = INFINITY;
    for (int k = 0; k < s.hull_points; ++k) {
      const Eigen::Vector3d p = T_cam_world * s.hull[k];
      z_min = std::min(z_min, p.z());
      if (p.z() <= 0.0) break;
      b.x_min = std::min(b.x_min, static_cast<float>(p.x() / p.z()));
      b.x_max = std::max(b.x_max, static_cast<float>(p.x() / p.z()));
      b.y_min = std::min(b.y_min, static_cast<float>(p.y() / p.z()));
      b.y_max = std::max(b.y_max, static_cast<float>(p.y() / p.z()));
    }
    if (s.hull_points == 0 || z_min <= 1.5 * s.hull_radius + 1e-3) {
      b = {-INFINITY, INFINITY, -INFINITY, INFINITY};
    } else {
      // A sphere of radius r at depth z spans at most r / (z - r) either
      // side in normalised coordinates (r / z at the axis, more off it).
      const float margin = static_cast<float>(s.hull_radius / (z_min - s.hull_radius)) * 2.0f;
      b = {b.x_min - margin, b.x_max + margin, b.y_min - margin, b.y_max + margin};
      if (s.hull_points == 2) {
        // A cable's box in the image is mostly empty when it runs
        // diagonally (any cable, once the camera rolls): keep its image as
        // a segment too.
        const Eigen::Vector3d p0 = T_cam_world * s.hull[0], p1 = T_cam_world * s.hull[1];
        seg = {true,
               static_cast<float>(p0.x() / p0.z()),
               static_cast<float>(p0.y() / p0.z()),
               static_cast<float>(p1.x() / p1.z()),
               static_cast<float>(p1.y() / p1.z()),
               margin};
      }
    }
    surface_bounds_.push_back(b);
    surface_segments_.push_back(seg);
  }
  // Each tile's list holds its surfaces grouped by kind, so that a ray's
  // walk through the list branches the same way from one surface to the
  // next (a jump on the kind per surface, mispredicted, cost more than
  // most of the tests themselves).
  by_kind_.clear();
  for (SurfaceKind kind : {SurfaceKind::kRect, SurfaceKind::kBox, SurfaceKind::kCylinder,
                           SurfaceKind::kRoundedBar, SurfaceKind::kMesh}) {
    for (std::size_t k = 0; k < scene.surfaces.size(); ++k) {
      if (scene.surfaces[k].kind == kind) by_kind_.push_back(static_cast<std::int32_t>(k));
    }
  }
  tile_surfaces_.clear();
  for (std::size_t t = 0; t < tile_bounds_.size(); ++t) {
    tile_begin_[t] = tile_surfaces_.size();
    const TileBounds& tb = tile_bounds_[t];
    for (std::int32_t k : by_kind_) {
      const TileBounds& sb = surface_bounds_[static_cast<std::size_t>(k)];
      if (sb.x_max < tb.x_min || sb.x_min > tb.x_max || sb.y_max < tb.y_min ||
          sb.y_min > tb.y_max) {
        continue;
      }
      const SegmentImage& seg = surface_segments_[static_cast<std::size_t>(k)];
      if (seg.valid && !segment_near_tile(seg, tb)) continue;
      tile_surfaces_.push_back(k);
    }
  }
  tile_begin_[tile_bounds_.size()] = tile_surfaces_.size();
}

void DepthRenderer::cast_rays(const Scene& scene, const Eigen::Isometry3d& T_world_cam) {
  cull_surfaces_per_tile(scene, T_world_cam);
  place_surfaces_in_view(scene, T_world_cam, &view_);
  const int w = static_cast<int>(cam_.width), h = static_cast<int>(cam_.height);
  const int tiles_x = (w + kTile - 1) / kTile;
  // Look a little past the sensor's range so that out-of-range surfaces
  // still read as "too far" rather than as nothing.
  const float t_max_m = static_cast<float>(settings_.range_max_m * 1.5);
  // Tile by tile, so each tile's surface list is looked up once.
  for (int ty = 0; ty < h; ty += kTile) {
    for (int tx = 0; tx < w; tx += kTile) {
      const std::size_t tile = static_cast<std::size_t>((ty / kTile) * tiles_x + tx / kTile);
      const std::int32_t* ids = tile_surfaces_.data() + tile_begin_[tile];
      const std::size_t count = tile_begin_[tile + 1] - tile_begin_[tile];
      for (int y = ty; y < std::min(h, ty + kTile); ++y) {
        for (int x = tx; x < std::min(w, tx + kTile); ++x) {
          const std::size_t i = static_cast<std::size_t>(y * w + x);
          ViewHit hit;
          if (intersect_view(view_.data(), ids, count, rays_[i], 1e-4f, t_max_m, &hit)) {
            range_[i] = hit.t_m;
            surface_[i] = hit.surface;
            cos_incidence_[i] = hit.cos_incidence;
            amplitude_[i] = view_[static_cast<std::size_t>(hit.surface)].reflectivity *
                            hit.cos_incidence / (hit.t_m * hit.t_m);
          } else {
            range_[i] = 0.0f;
            surface_[i] = -1;
            cos_incidence_[i] = 0.0f;
            amplitude_[i] = 0.0f;
          }
        }
      }
    }
  }
}

namespace {

// flying_pixel_threshold_m for four ranges at once.
Floats4 flying_pixel_threshold_m(Floats4 range_m) {
  const Floats4 ramp = 0.018f + (range_m - 1.0f) * (0.122f / 3.5f);
  const Floats4 low = {0.018f, 0.018f, 0.018f, 0.018f}, high = {0.14f, 0.14f, 0.14f, 0.14f};
  const Floats4 at_least_low = ramp > low ? ramp : low;
  return at_least_low < high ? at_least_low : high;
}

Floats4 abs_floats4(Floats4 v) {
  return v < 0.0f ? -v : v;
}

}  // namespace

// Of a pixel's four neighbours with a hit, the one whose depth differs
// most from the pixel's (the first of up, down, left, right on a tie): its
// range and the size of the jump (0 and the pixel's own range if none).
void DepthRenderer::largest_jump_neighbour(int row, int col, float* jump_m, float* other_m) const {
  const int w = static_cast<int>(cam_.width), h = static_cast<int>(cam_.height);
  const float r = range_[static_cast<std::size_t>(row * w + col)];
  float far_jump = 0.0f, other = r;
  const int dr[4] = {-1, 1, 0, 0}, dc[4] = {0, 0, -1, 1};
  for (int k = 0; k < 4; ++k) {
    const int rr = row + dr[k], cc = col + dc[k];
    if (rr < 0 || cc < 0 || rr >= h || cc >= w) continue;
    const float rn = range_[static_cast<std::size_t>(rr * w + cc)];
    if (rn > 0.0f && std::fabs(rn - r) > far_jump) {
      far_jump = std::fabs(rn - r);
      other = rn;
    }
  }
  *jump_m = far_jump;
  *other_m = other;
}

// A pixel is on an edge when that neighbour jumps more than the vendor
// threshold and is the nearer.
bool DepthRenderer::is_flying_candidate(int row, int col) const {
  const float r = range_[static_cast<std::size_t>(row * static_cast<int>(cam_.width) + col)];
  if (r <= 0.0f) return false;
  float jump = 0.0f, other = r;
  largest_jump_neighbour(row, col, &jump, &other);
  return jump > flying_pixel_threshold_m(r) && other < r;
}

void DepthRenderer::add_flying_pixels(std::uint64_t stream_seed) {
  const int w = static_cast<int>(cam_.width), h = static_cast<int>(cam_.height);
  // First which pixels sit on an edge (four at a time inside the image),
  // then the random draws for those alone, in pixel order, so the draws do
  // not depend on how the first pass is blocked.
  std::uint8_t* candidate = flying_candidate_.data();
  const Floats4 zero = {0.0f, 0.0f, 0.0f, 0.0f};
  for (int row = 0; row < h; ++row) {
    std::uint8_t* out = candidate + row * w;
    if (row == 0 || row == h - 1) {
      for (int col = 0; col < w; ++col) out[col] = is_flying_candidate(row, col);
      continue;
    }
    out[0] = is_flying_candidate(row, 0);
    int col = 1;
    for (; col + 4 <= w - 1; col += 4) {
      const float* at = range_.data() + row * w + col;
      const Floats4 r = load_floats4(at);
      Floats4 far_jump = zero, other = r;
      for (const float* n : {at - w, at + w, at - 1, at + 1}) {
        const Floats4 rn = load_floats4(n);
        const Floats4 jump = abs_floats4(rn - r);
        const Ints4 take = (rn > zero) & (jump > far_jump);
        far_jump = take ? jump : far_jump;
        other = take ? rn : other;
      }
      const Ints4 edge = (r > zero) & (far_jump > flying_pixel_threshold_m(r)) & (other < r);
      for (int k = 0; k < 4; ++k) out[col + k] = edge[k] != 0;
    }
    for (; col < w; ++col) out[col] = is_flying_candidate(row, col);
  }
  SimRandom rng(stream_seed);
  const std::size_t n = range_.size();
  for (std::size_t i = 0; i < n; ++i) {
    if (!candidate[i] || !(rng.uniform() < settings_.flying_probability)) continue;
    // Only the farther pixel of an edge is mixed: the nearer surface
    // covers the footprint's edge, the background shows through it.
    const float r = range_[i];
    float jump = 0.0f, other = r;
    largest_jump_neighbour(static_cast<int>(i) / w, static_cast<int>(i) % w, &jump, &other);
    const float mix = static_cast<float>(rng.uniform());
    measured_[i] = mix * r + (1.0f - mix) * other;
  }
}

namespace {

// How many of a pixel's window samples (every second pixel of the window,
// starting at its first column and row inside the image) lie 1 to 15 cm
// nearer than `r`, and how many samples there are.
void count_nearer_in_window(const float* range_m, int w, int h, int row, int col, int win, float r,
                            int* nearer, int* total) {
  // "1 to 15 cm nearer, and a hit" as one open interval of ranges (the
  // four-wide count in add_multipath tests it the same way).
  const float near_end = r - 0.01f, lower = std::max(r - 0.15f, 0.0f);
  int n = 0, t = 0;
  for (int rr = std::max(0, row - win); rr <= std::min(h - 1, row + win); rr += 2) {
    for (int cc = std::max(0, col - win); cc <= std::min(w - 1, col + win); cc += 2) {
      const float rn = range_m[static_cast<std::size_t>(rr * w + cc)];
      ++t;
      n += rn > lower && rn < near_end;
    }
  }
  *nearer = n;
  *total = t;
}

}  // namespace

void DepthRenderer::add_multipath() {
  const int w = static_cast<int>(cam_.width), h = static_cast<int>(cam_.height);
  const int win = settings_.multipath_window_px;
  const double gain = settings_.multipath_gain_m;
  const float* range = range_.data();
  auto bias_at_edge = [&](int row, int col) {
    const std::size_t i = static_cast<std::size_t>(row * w + col);
    int nearer = 0, total = 0;
    count_nearer_in_window(range, w, h, row, col, win, range[i], &nearer, &total);
    bias_[i] = range[i] > 0.0f ? static_cast<float>(gain * nearer / std::max(total, 1)) : 0.0f;
  };
  // Inside, four pixels at a time and for every pixel (no test for "is
  // anything nearer" first: counting densely is cheaper than branching).
  // A pixel with no hit has range 0, which is never 1 cm farther than a
  // sample, so its count and bias are 0.
  const Floats4 zero = {0.0f, 0.0f, 0.0f, 0.0f};
  for (int row = 0; row < h; ++row) {
    if (row < win || row >= h - win) {
      for (int col = 0; col < w; ++col) bias_at_edge(row, col);
      continue;
    }
    int col = 0;
    for (; col < win; ++col) bias_at_edge(row, col);
    for (; col + 4 <= w - win; col += 4) {
      // "1 to 15 cm nearer, and a hit" as one open interval of ranges.
      const Floats4 r = load_floats4(range + row * w + col);
      const Floats4 far_end = r - 0.15f, near_end = r - 0.01f;
      const Floats4 lower = far_end > zero ? far_end : zero;
      Ints4 count = {0, 0, 0, 0};
      for (int dr = -win; dr <= win; dr += 2) {
        const float* line = range + (row + dr) * w + col;
        for (int dc = -win; dc <= win; dc += 2) {
          const Floats4 rn = load_floats4(line + dc);
          count -= (rn > lower) & (rn < near_end);  // true lanes are -1
        }
      }
      float* out = bias_.data() + row * w + col;
      for (int k = 0; k < 4; ++k) out[k] = bias_for_count_[static_cast<std::size_t>(count[k])];
    }
    for (; col < w; ++col) bias_at_edge(row, col);
  }
}

void DepthRenderer::apply_flying_filter(std::vector<hal::DepthPoint>* out) {
  const int w = static_cast<int>(cam_.width), h = static_cast<int>(cam_.height);
  std::vector<hal::DepthPoint>& pts = *out;
  // Decided on the unfiltered depths (point_z_, 0 where invalid), then
  // applied, so the filter does not feed on its own output.
  const float* z = point_z_.data();
  auto jump = [](float zi, float zn, float th) { return zn > 0.0f && std::fabs(zi - zn) > th; };
  auto drop_one = [&](int i) {
    const float th = flying_pixel_threshold_m(z[i]);
    return z[i] > 0.0f && ((jump(z[i], z[i - 1], th) && jump(z[i], z[i + 1], th)) ||
                           (jump(z[i], z[i - w], th) && jump(z[i], z[i + w], th)));
  };
  auto invalidate = [&](int i) {
    pts[static_cast<std::size_t>(i)] =
        hal::DepthPoint{0.0f, 0.0f, 0.0f, 0.0f, pts[static_cast<std::size_t>(i)].gray_value, 0};
  };
  const Floats4 zero = {0.0f, 0.0f, 0.0f, 0.0f};
  for (int row = 1; row < h - 1; ++row) {
    int col = 1;
    for (; col + 4 <= w - 1; col += 4) {
      const int i = row * w + col;
      const Floats4 zi = load_floats4(z + i), th = flying_pixel_threshold_m(zi);
      auto jumps = [&](int offset) {
        const Floats4 zn = load_floats4(z + i + offset);
        return (zn > zero) & (abs_floats4(zi - zn) > th);
      };
      const Ints4 drop = (zi > zero) & ((jumps(-1) & jumps(1)) | (jumps(-w) & jumps(w)));
      for (int k = 0; k < 4; ++k) {
        if (drop[k]) invalidate(i + k);
      }
    }
    for (; col < w - 1; ++col) {
      if (drop_one(row * w + col)) invalidate(row * w + col);
    }
  }
}

}  // namespace sim_hal

namespace sim_hal {

void DepthRenderer::render(const Scene& scene, const Eigen::Isometry3d& T_world_cam,
                           std::uint64_t seed, std::uint64_t frame_index,
                           std::vector<hal::DepthPoint>* out) {
  const ToFSettings& s = settings_;
  const std::size_t n = rays_.size();
  out->resize(n);
  cast_rays(scene, T_world_cam);
  std::copy(range_.begin(), range_.end(), measured_.begin());

  // Auto exposure on the 95th percentile of the unscaled amplitude.
  sorted_.clear();
  for (std::size_t i = 0; i < n; ++i) {
    if (range_[i] > 0.0f) sorted_.push_back(amplitude_[i]);
  }
  double exposure = s.max_exposure;
  if (!sorted_.empty()) {
    const std::size_t k = sorted_.size() * 95 / 100;
    std::nth_element(sorted_.begin(), sorted_.begin() + static_cast<std::ptrdiff_t>(k),
                     sorted_.end());
    if (sorted_[k] > 0.0f) exposure = std::min(s.max_exposure, s.amplitude_target / sorted_[k]);
  }

  if (s.flying_pixels) add_flying_pixels(mix_seed(seed, frame_index, 1));
  if (s.multipath) add_multipath();
  // One normal draw per pixel, in pixel order, used or not, so that
  // switching one effect off leaves the others' random numbers where they
  // were.
  SimRandom noise_rng(mix_seed(seed, frame_index, 2));
  for (std::size_t i = 0; i < n; ++i) noise_draw_[i] = static_cast<float>(noise_rng.normal());

  // Single precision from here: the noise floor is 0.8 mm, float's step at
  // 6 m is 0.5 um.
  const float exposure_f = static_cast<float>(exposure);
  const float noise_min = static_cast<float>(s.noise_min_m),
              noise_ref = static_cast<float>(s.noise_ref_m),
              amplitude_ref = static_cast<float>(s.amplitude_ref),
              range_min = static_cast<float>(s.range_min_m),
              range_max = static_cast<float>(s.range_max_m),
              amplitude_min = static_cast<float>(s.amplitude_min),
              amplitude_max = static_cast<float>(s.amplitude_saturation),
              grazing_cos_min = static_cast<float>(s.grazing_cos_min),
              noise_cutoff = static_cast<float>(s.noise_cutoff_m);
  for (std::size_t i = 0; i < n; ++i) {
    hal::DepthPoint& p = (*out)[i];
    const float amplitude = amplitude_[i] * exposure_f;
    const std::uint16_t gray = static_cast<std::uint16_t>(std::min(amplitude, 4095.0f));
    const float sigma =
        std::max(noise_min, noise_ref * std::sqrt(amplitude_ref / std::max(amplitude, 1e-3f)));
    const float range = range_[i];
    bool valid = range > 0.0f;
    if (s.invalid_pixels) {
      valid = valid && range >= range_min && range <= range_max && amplitude >= amplitude_min &&
              amplitude <= amplitude_max && cos_incidence_[i] >= grazing_cos_min &&
              sigma <= noise_cutoff;
    }
    if (!valid) {
      p = hal::DepthPoint{0.0f, 0.0f, 0.0f, 0.0f, gray, 0};
      point_z_[i] = 0.0f;
      continue;
    }
    float r = measured_[i];
    if (s.multipath) r += bias_[i];
    if (s.noise) r += sigma * noise_draw_[i];
    const Eigen::Vector3f& ray = rays_[i];
    p.x_m = ray.x() * r;
    p.y_m = ray.y() * r;
    p.z_m = ray.z() * r;
    point_z_[i] = p.z_m;
    p.noise_m = s.noise ? sigma : 0.0f;
    p.gray_value = gray;
    p.confidence =
        static_cast<std::uint8_t>(std::clamp(255.0f * (1.0f - sigma / noise_cutoff), 1.0f, 255.0f));
  }
  if (s.flying_filter) apply_flying_filter(out);
}

}  // namespace sim_hal
