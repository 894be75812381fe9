#include "sim_hal/tof_sensor.hpp"

#include <algorithm>
#include <cmath>

#include "sim_hal/sim_random.hpp"

namespace sim_hal {

double flying_pixel_threshold_m(double range_m) {
  if (range_m <= 1.0) return 0.018;
  if (range_m >= 4.5) return 0.14;
  return 0.018 + (0.14 - 0.018) * (range_m - 1.0) / 3.5;
}

namespace {
constexpr int kTile = 8;
}

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
  row_nearest_.resize(n);
  far_range_.resize(n);
  surface_.resize(n);
  sorted_.reserve(n);
}

void DepthRenderer::cull_surfaces_per_tile(const Scene& scene,
                                           const Eigen::Isometry3d& T_world_cam) {
  const Eigen::Isometry3d T_cam_world = T_world_cam.inverse();
  // Each surface's extent in normalised image coordinates: the pinhole
  // image of a convex hull is the hull of its points' images, widened by
  // the hull's radius at its nearest depth. A hull reaching behind the
  // image plane could cover any direction: every tile keeps it.
  surface_bounds_.clear();
  for (const Surface& s : scene.surfaces) {
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
    }
    surface_bounds_.push_back(b);
  }
  tile_surfaces_.clear();
  for (std::size_t t = 0; t < tile_bounds_.size(); ++t) {
    tile_begin_[t] = tile_surfaces_.size();
    const TileBounds& tb = tile_bounds_[t];
    for (std::size_t k = 0; k < scene.surfaces.size(); ++k) {
      const TileBounds& sb = surface_bounds_[k];
      if (sb.x_max < tb.x_min || sb.x_min > tb.x_max || sb.y_max < tb.y_min ||
          sb.y_min > tb.y_max) {
        continue;
      }
      tile_surfaces_.push_back(static_cast<std::int32_t>(k));
    }
  }
  tile_begin_[tile_bounds_.size()] = tile_surfaces_.size();
}

void DepthRenderer::cast_rays(const Scene& scene, const Eigen::Isometry3d& T_world_cam) {
  cull_surfaces_per_tile(scene, T_world_cam);
  const Eigen::Vector3d origin = T_world_cam.translation();
  const Eigen::Matrix3d R = T_world_cam.rotation();
  const int w = static_cast<int>(cam_.width), h = static_cast<int>(cam_.height);
  const int tiles_x = (w + kTile - 1) / kTile;
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const std::size_t i = static_cast<std::size_t>(y * w + x);
      const std::size_t tile = static_cast<std::size_t>((y / kTile) * tiles_x + x / kTile);
      const Eigen::Vector3d dir = R * rays_[i].cast<double>();
      Hit hit;
      // Look a little past the sensor's range so that out-of-range surfaces
      // still read as "too far" rather than as nothing.
      if (intersect_surfaces(scene, tile_surfaces_.data() + tile_begin_[tile],
                             tile_begin_[tile + 1] - tile_begin_[tile], origin, dir, 1e-4,
                             settings_.range_max_m * 1.5, &hit)) {
        range_[i] = static_cast<float>(hit.t);
        surface_[i] = hit.surface;
        cos_incidence_[i] = static_cast<float>(std::fabs(hit.normal.dot(dir)));
        const double refl = scene.surfaces[static_cast<std::size_t>(hit.surface)].reflectivity;
        amplitude_[i] = static_cast<float>(refl * cos_incidence_[i] / (hit.t * hit.t));
      } else {
        range_[i] = 0.0f;
        surface_[i] = -1;
        cos_incidence_[i] = 0.0f;
        amplitude_[i] = 0.0f;
      }
    }
  }
}

void DepthRenderer::add_flying_pixels(std::uint64_t stream_seed) {
  const int w = static_cast<int>(cam_.width), h = static_cast<int>(cam_.height);
  SimRandom rng(stream_seed);
  for (int row = 0; row < h; ++row) {
    for (int col = 0; col < w; ++col) {
      const std::size_t i = static_cast<std::size_t>(row * w + col);
      const float r = range_[i];
      if (r <= 0.0f) continue;
      float far_jump = 0.0f, other = r;
      const int dr[4] = {-1, 1, 0, 0}, dc[4] = {0, 0, -1, 1};
      for (int k = 0; k < 4; ++k) {
        const int rr = row + dr[k], cc = col + dc[k];
        if (rr < 0 || cc < 0 || rr >= h || cc >= w) continue;
        const float rn = range_[static_cast<std::size_t>(rr * w + cc)];
        if (rn <= 0.0f) continue;
        if (std::fabs(rn - r) > far_jump) {
          far_jump = std::fabs(rn - r);
          other = rn;
        }
      }
      // Only the farther pixel of an edge is mixed: the nearer surface
      // covers the footprint's edge, the background shows through it.
      if (far_jump > flying_pixel_threshold_m(r) && other < r &&
          rng.uniform() < settings_.flying_probability) {
        const float mix = static_cast<float>(rng.uniform());
        measured_[i] = mix * r + (1.0f - mix) * other;
      }
    }
  }
}

void DepthRenderer::add_multipath() {
  const int w = static_cast<int>(cam_.width), h = static_cast<int>(cam_.height);
  const int win = settings_.multipath_window_px;
  // Most pixels see nothing nearer in their window (a flat wall): the
  // window's nearest range, by a separable min filter over the same
  // stride-2 samples, rules them out before counting. No hit reads as
  // infinitely far, so the filter is a plain minimum.
  const std::size_t n = range_.size();
  for (std::size_t i = 0; i < n; ++i) far_range_[i] = range_[i] > 0.0f ? range_[i] : INFINITY;
  for (int row = 0; row < h; ++row) {
    const float* line = far_range_.data() + static_cast<std::size_t>(row * w);
    float* out = row_nearest_.data() + static_cast<std::size_t>(row * w);
    for (int col = 0; col < w; ++col) {
      float m = INFINITY;
      for (int cc = std::max(0, col - win); cc <= std::min(w - 1, col + win); cc += 2) {
        m = std::min(m, line[cc]);
      }
      out[col] = m;
    }
  }
  for (int row = 0; row < h; ++row) {
    for (int col = 0; col < w; ++col) {
      const std::size_t i = static_cast<std::size_t>(row * w + col);
      bias_[i] = 0.0f;
      const float r = range_[i];
      if (r <= 0.0f) continue;
      float nearest = INFINITY;
      for (int rr = std::max(0, row - win); rr <= std::min(h - 1, row + win); rr += 2) {
        nearest = std::min(nearest, row_nearest_[static_cast<std::size_t>(rr * w + col)]);
      }
      if (!(r - nearest > 0.01f)) continue;
      int nearer = 0, total = 0;
      for (int rr = std::max(0, row - win); rr <= std::min(h - 1, row + win); rr += 2) {
        for (int cc = std::max(0, col - win); cc <= std::min(w - 1, col + win); cc += 2) {
          const float rn = range_[static_cast<std::size_t>(rr * w + cc)];
          ++total;
          nearer += rn > 0.0f && r - rn > 0.01f && r - rn < 0.15f;
        }
      }
      bias_[i] = static_cast<float>(settings_.multipath_gain_m * nearer / std::max(total, 1));
    }
  }
}

void DepthRenderer::apply_flying_filter(std::vector<hal::DepthPoint>* out) {
  const int w = static_cast<int>(cam_.width), h = static_cast<int>(cam_.height);
  std::vector<hal::DepthPoint>& pts = *out;
  auto jump = [&](std::size_t a, std::size_t b, float th) {
    return pts[b].confidence != 0 && std::fabs(pts[a].z_m - pts[b].z_m) > th;
  };
  // Decide on the unfiltered frame, then invalidate, so the filter does not
  // feed on its own output.
  std::vector<std::uint8_t>& drop = drop_;
  drop.assign(pts.size(), 0);
  for (int row = 1; row < h - 1; ++row) {
    for (int col = 1; col < w - 1; ++col) {
      const std::size_t i = static_cast<std::size_t>(row * w + col);
      if (pts[i].confidence == 0) continue;
      const float th = static_cast<float>(flying_pixel_threshold_m(pts[i].z_m));
      drop[i] = (jump(i, i - 1, th) && jump(i, i + 1, th)) ||
                (jump(i, i - static_cast<std::size_t>(w), th) &&
                 jump(i, i + static_cast<std::size_t>(w), th));
    }
  }
  for (std::size_t i = 0; i < pts.size(); ++i) {
    if (drop[i]) pts[i] = hal::DepthPoint{0.0f, 0.0f, 0.0f, 0.0f, pts[i].gray_value, 0};
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
  SimRandom noise_rng(mix_seed(seed, frame_index, 2));

  for (std::size_t i = 0; i < n; ++i) {
    hal::DepthPoint& p = (*out)[i];
    const double amplitude = amplitude_[i] * exposure;
    p.gray_value = static_cast<std::uint16_t>(std::min(amplitude, 4095.0));
    const double sigma = std::max(
        s.noise_min_m, s.noise_ref_m * std::sqrt(s.amplitude_ref / std::max(amplitude, 1e-3)));
    // Draw the noise for every pixel, used or not, so that switching one
    // effect off leaves the others' random numbers where they were.
    const double noise = noise_rng.normal();
    bool valid = range_[i] > 0.0f;
    if (s.invalid_pixels && valid) {
      valid = range_[i] >= s.range_min_m && range_[i] <= s.range_max_m &&
              amplitude >= s.amplitude_min && amplitude <= s.amplitude_saturation &&
              cos_incidence_[i] >= s.grazing_cos_min && sigma <= s.noise_cutoff_m;
    }
    if (!valid) {
      p = hal::DepthPoint{0.0f, 0.0f, 0.0f, 0.0f, p.gray_value, 0};
      continue;
    }
    double r = measured_[i];
    if (s.multipath) r += bias_[i];
    if (s.noise) r += sigma * noise;
    const Eigen::Vector3f q = rays_[i] * static_cast<float>(r);
    p.x_m = q.x();
    p.y_m = q.y();
    p.z_m = q.z();
    p.noise_m = static_cast<float>(s.noise ? sigma : 0.0);
    p.confidence =
        static_cast<std::uint8_t>(std::clamp(255.0 * (1.0 - sigma / s.noise_cutoff_m), 1.0, 255.0));
  }
  if (s.flying_filter) apply_flying_filter(out);
}

}  // namespace sim_hal
