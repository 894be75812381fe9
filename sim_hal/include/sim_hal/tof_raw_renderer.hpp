#pragma once
// The simulated Pico Flexx at the imager: renders the raw phase images a
// continuous-wave time-of-flight camera reads out (tof/raw_frame.hpp), for
// the robot's own processing (drivers/pico_flexx/tof) to turn into depth.
//
// The rays are cast by DepthRenderer (tof_sensor.hpp, which stays the
// depth-level reference); from each pixel's returns this forms, per
// modulation frequency, the correlation samples at 0, 90, 180, 270 deg:
//  - returns add as phasors: the pixel's own return, its footprint's share
//    of its four neighbours' (mixed returns at depth edges: flying pixels)
//    and light bounced off nearer surfaces close by (multipath);
//  - amplitude = exposure * reflectivity * cos(incidence) / range^2, the
//    signal's background = amplitude / modulation contrast, ambient light
//    from the surface's reflectivity, both growing with exposure;
//  - the unit's calibration as a real sensor shows it: each pixel's
//    fixed-pattern offset, each frequency's phase offset, wiggling,
//    temperature drift;
//  - shot noise (variance = collected signal and ambient over the
//    conversion gain), read noise, 12-bit quantisation and saturation.
// Deterministic for a seed and frame index.
#include <Eigen/Geometry>
#include <cstdint>
#include <vector>

#include "sim_hal/camera_model.hpp"
#include "sim_hal/scene.hpp"
#include "sim_hal/tof_sensor.hpp"
#include "tof/calibration.hpp"
#include "tof/raw_frame.hpp"

namespace sim_hal {

struct RawRenderSettings {
  // Amplitude in DN per microsecond of exposure of a surface of
  // reflectivity 1 seen square on at 1 m.
  double amplitude_dn_per_us_m2 = 2.0;
  // Auto exposure: the 95th percentile of the frame's amplitudes at this,
  // never longer than the use case's longest exposure.
  bool auto_exposure = true;
  double amplitude_target_dn = 1200.0;
  std::uint32_t manual_exposure_us = 1000;
  // The signal's background per unit of amplitude is 1 / contrast.
  double modulation_contrast = 0.7;
  // Ambient (cabin) light collected per microsecond by a surface of
  // reflectivity 1, in DN.
  double ambient_dn_per_us = 0.05;
  // Mixed returns at depth edges: where a pixel and a neighbour see
  // different surfaces (or one surface folding out of sight), the edge
  // between them lies somewhere between the two pixels' centres (uniform,
  // drawn per pair and frame); each pixel's footprint then takes in the
  // part of the other surface that lies inside its own area.
  bool footprint_edges = true;
  // Multipath: a surface 1 to 15 cm nearer, sampled on a ring of eight
  // pixels this far away, sends this share of its amplitude (each) along
  // the longer path camera -> it -> this pixel's surface -> camera.
  bool multipath = true;
  double multipath_gain = 0.04;
  int multipath_ring_px = 4;
  bool noise = true;
  double sensor_temperature_c = 35.0;
};

// A unit's calibration as the simulator's camera has it: the lens, 60 and
// 80 MHz (7.49 m unambiguous together), and phase offsets,
// wiggling, a fixed pattern and a temperature drift that vary with
// `camera_seed` the way units differ. `pixel_pattern_m` > 0 adds a
// per-pixel table of that standard deviation (the file grows to ~200 kB).
tof::Calibration simulated_calibration(const CameraIntrinsics& cam, std::uint64_t camera_seed,
                                       double pixel_pattern_m = 0.0);

class RawRenderer {
 public:
  // `calibration` is the camera's truth (written to a file with
  // tof::write_calibration_file for the processing to read).
  RawRenderer(const CameraIntrinsics& cam, const ToFSettings& depth_settings,
              const RawRenderSettings& settings, const tof::Calibration& calibration);

  // Renders one raw frame of `mode` with exposures up to max_exposure_us.
  void render(const Scene& scene, const Eigen::Isometry3d& T_world_cam, tof::Mode mode,
              std::uint32_t max_exposure_us, std::uint64_t seed, std::uint64_t frame_index,
              tof::RawFrame* out);

  // The last frame's exact ranges (0 = no hit), for tests against truth.
  const std::vector<float>& true_range_m() const { return caster_.true_range_m(); }
  const RawRenderSettings& settings() const { return settings_; }
  RawRenderSettings& settings() { return settings_; }

 private:
  std::uint32_t choose_exposure_us(std::uint32_t max_exposure_us);
  void gather_returns(const Scene& scene, double exposure_us);
  void form_phasors(int frequency, double temperature_offset_m);
  void find_multipath();
  void find_edges(std::uint64_t stream_seed);
  void write_samples(int frequency, tof::RawFrame* out, std::uint64_t stream_seed);
  void draw_normals(std::size_t count, std::uint64_t stream_seed);
  void write_grey(tof::RawFrame* out, std::uint64_t stream_seed);

  DepthRenderer caster_;
  RawRenderSettings settings_;
  tof::Calibration calibration_;
  // Per pixel, computed at construction: each frequency's fixed phase
  // (pixel offset and the frequency's offset), as cos and sin.
  std::vector<float> fixed_cos_[tof::kMaxFrequencies], fixed_sin_[tof::kMaxFrequencies];
  // Per frame: each pixel's own return (amplitude, background, ambient in
  // DN), its phasor, and the summed phasor and background of its footprint.
  std::vector<float> amplitude_, background_, ambient_;
  std::vector<float> own_re_, own_im_, sum_re_, sum_im_, sum_background_;
  // Per frame: the share of each pixel's area that sees its upper, lower,
  // left and right neighbour's surface (0 off an edge).
  std::vector<float> edge_share_[4];
  // The pixels with a share (the first edge_count_), and which they are.
  std::vector<std::int32_t> edge_pixels_;
  std::vector<std::uint8_t> on_edge_;
  std::size_t edge_count_ = 0;
  // Per frame: the multipath return each pixel gets (amplitude in DN, 0 for
  // none, and its one-way equivalent path), found once for all frequencies.
  std::vector<float> multipath_amplitude_, multipath_path_m_;
  // The four phase steps' mean levels (DN) and the noise draws, four per
  // pixel, of the frequency being written.
  std::vector<float> step_mean_[4];
  std::vector<float> normals_;
  std::vector<float> sorted_;
};

}  // namespace sim_hal
