#pragma once
// The time-of-flight sensor model: turns exact ray hits into what a Pico
// Flexx reports. Every effect has a switch and its parameters; the model is
// deterministic for a given seed and frame index. See sim_hal/README.md.
#include <Eigen/Geometry>
#include <cstdint>
#include <vector>

#include "hal/depth_frame.hpp"
#include "sim_hal/camera_model.hpp"
#include "sim_hal/scene.hpp"
#include "sim_hal/view_surfaces.hpp"

namespace sim_hal {

struct ToFSettings {
  double range_min_m = 0.1;
  double range_max_m = 4.0;

  // Amplitude = exposure * reflectivity * cos(incidence) / range^2, with the
  // exposure set per frame (auto exposure) so that the 95th percentile sits
  // at amplitude_target, but never above max_exposure.
  double amplitude_target = 2000.0;
  double max_exposure = 2000.0;

  // Axial (along the ray) noise: sigma = noise_ref_m * sqrt(amplitude_ref /
  // amplitude), at least noise_min_m. Lower amplitude (farther, darker,
  // more oblique) means more noise.
  bool noise = true;
  double noise_ref_m = 0.003;
  double amplitude_ref = 2000.0;
  double noise_min_m = 0.0008;

  // Flying pixels: a pixel on a depth discontinuity (a jump to a neighbour
  // above the vendor's threshold) mixes the two depths with this probability.
  bool flying_pixels = true;
  double flying_probability = 0.7;
  // The vendor's filter that invalidates pixels jumping to both neighbours.
  bool flying_filter = true;

  // Invalid pixels: low amplitude, saturation, grazing incidence, out of
  // range, noise above the vendor's cut-off.
  bool invalid_pixels = true;
  double amplitude_min = 40.0;
  double amplitude_saturation = 3750.0;
  double grazing_cos_min = 0.12;  // about 83 deg from the surface normal
  double noise_cutoff_m = 0.07;

  // Multipath: light bounced off a nearby raised surface lengthens the path
  // in concave corners (a leg meeting the wall). Bias = gain * the fraction
  // of the window's pixels 1..15 cm nearer than this one (the window
  // sampled every second pixel).
  bool multipath = true;
  double multipath_gain_m = 0.008;
  int multipath_window_px = 3;
};

// The vendor's flying-pixel threshold: 0.018 m up to 1 m, rising linearly to
// 0.14 m at 4.5 m.
float flying_pixel_threshold_m(float range_m);

class DepthRenderer {
 public:
  DepthRenderer(const CameraIntrinsics& cam, const ToFSettings& settings);

  // Renders one frame. `out` is resized to width * height once and reused.
  void render(const Scene& scene, const Eigen::Isometry3d& T_world_cam, std::uint64_t seed,
              std::uint64_t frame_index, std::vector<hal::DepthPoint>* out);

  // Only casts the rays (no sensor effects): fills true_range_m(),
  // hit_surface(), cos_incidence() and unit_amplitude() for the raw-frame
  // renderer (tof_raw_renderer.hpp), which forms its own samples from them.
  void cast(const Scene& scene, const Eigen::Isometry3d& T_world_cam) {
    cast_rays(scene, T_world_cam);
  }
  // The last cast's reflectivity * cos(incidence) / range^2 (0 = no hit),
  // before exposure, and |cos| of the incidence.
  const std::vector<float>& unit_amplitude() const { return amplitude_; }
  const std::vector<float>& cos_incidence() const { return cos_incidence_; }
  const std::vector<Eigen::Vector3f>& rays() const { return rays_; }

  const CameraIntrinsics& camera() const { return cam_; }
  const ToFSettings& settings() const { return settings_; }
  // The last frame's exact ranges (0 = no hit) and hit surfaces (-1 = none).
  const std::vector<float>& true_range_m() const { return range_; }
  const std::vector<std::int32_t>& hit_surface() const { return surface_; }

 private:
  void cast_rays(const Scene& scene, const Eigen::Isometry3d& T_world_cam);
  // Per 8 x 8 pixel tile (kTile), the surfaces whose hull, seen through a pinhole,
  // overlaps the tile's rays.
  void cull_surfaces_per_tile(const Scene& scene, const Eigen::Isometry3d& T_world_cam);
  void add_flying_pixels(std::uint64_t stream_seed);
  void largest_jump_neighbour(int row, int col, float* jump_m, float* other_m) const;
  bool is_flying_candidate(int row, int col) const;
  void add_multipath();
  void apply_flying_filter(std::vector<hal::DepthPoint>* out);

  CameraIntrinsics cam_;
  ToFSettings settings_;
  std::vector<Eigen::Vector3f> rays_;
  std::vector<float> range_, measured_, amplitude_, cos_incidence_, bias_, noise_draw_, point_z_;
  std::vector<std::int32_t> surface_;
  std::vector<float> sorted_;
  std::vector<float> bias_for_count_;  // multipath bias by nearer-sample count
  std::vector<std::uint8_t> flying_candidate_;
  // Tiles: the range of their rays' normalised image coordinates (x/z, y/z
  // before distortion, which is what a pinhole projection of the scene
  // gives), and the surfaces each tile may see (offsets into
  // tile_surfaces_).
  struct TileBounds {
    float x_min, x_max, y_min, y_max;
  };
  // A two-point hull's (cable, bar) image: the segment between its end
  // points' images and how far either side of it the surface may reach.
  struct SegmentImage {
    bool valid;
    float x0, y0, x1, y1, margin;
  };
  static bool segment_near_tile(const SegmentImage& seg, const TileBounds& tile);
  std::vector<TileBounds> tile_bounds_;
  std::vector<TileBounds> surface_bounds_;
  std::vector<SegmentImage> surface_segments_;
  std::vector<std::size_t> tile_begin_;
  std::vector<std::int32_t> tile_surfaces_;
  std::vector<std::int32_t> by_kind_;  // surface indices, grouped by kind
  std::vector<ViewSurface> view_;      // the scene in this frame's camera frame
};

}  // namespace sim_hal
