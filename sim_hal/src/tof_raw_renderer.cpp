#include "sim_hal/tof_raw_renderer.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstring>

#include "sim_hal/sim_random.hpp"

namespace sim_hal {
namespace {

// The round trip's phase per metre of range at `hz`: 4 pi f / c.
double phase_per_m(double hz) {
  return 4.0 * M_PI * hz / tof::kSpeedOfLight_m_s;
}

}  // namespace

RawRenderer::RawRenderer(const CameraIntrinsics& cam, const ToFSettings& depth_settings,
                         const RawRenderSettings& settings, const tof::Calibration& calibration)
    : caster_(cam, depth_settings), settings_(settings), calibration_(calibration) {
  const std::size_t n = static_cast<std::size_t>(cam.width) * cam.height;
  // The raw frame is the Pico Flexx's imager (and the vector passes work
  // in whole blocks of four pixels).
  assert(n == tof::kPixels);
  for (int f = 0; f < calibration.frequency_count; ++f) {
    const double k = phase_per_m(calibration.frequency[f].frequency_hz);
    fixed_cos_[f].resize(n);
    fixed_sin_[f].resize(n);
    for (std::uint32_t row = 0; row < cam.height; ++row) {
      for (std::uint32_t col = 0; col < cam.width; ++col) {
        const double phase = k * tof::pixel_offset_m(calibration, row, col) +
                             calibration.frequency[f].phase_offset_rad;
        fixed_cos_[f][row * cam.width + col] = static_cast<float>(std::cos(phase));
        fixed_sin_[f][row * cam.width + col] = static_cast<float>(std::sin(phase));
      }
    }
  }
  for (std::vector<float>* v :
       {&amplitude_, &background_, &ambient_, &own_re_, &own_im_, &sum_re_, &sum_im_,
        &sum_background_, &multipath_amplitude_, &multipath_path_m_, &step_mean_[0], &step_mean_[1],
        &step_mean_[2], &step_mean_[3], &edge_share_[0], &edge_share_[1], &edge_share_[2],
        &edge_share_[3]}) {
    v->resize(n);
  }
  normals_.resize(4 * n);
  edge_pixels_.resize(n);
  on_edge_.resize(n);
  sorted_.reserve(n);
}

std::uint32_t RawRenderer::choose_exposure_us(std::uint32_t max_exposure_us) {
  if (!settings_.auto_exposure) return std::min(settings_.manual_exposure_us, max_exposure_us);
  const std::vector<float>& unit = caster_.unit_amplitude();
  sorted_.clear();
  for (float a : unit) {
    if (a > 0.0f) sorted_.push_back(a);
  }
  if (sorted_.empty()) return max_exposure_us;
  const std::size_t k = sorted_.size() * 95 / 100;
  std::nth_element(sorted_.begin(), sorted_.begin() + static_cast<std::ptrdiff_t>(k),
                   sorted_.end());
  const double wanted = settings_.amplitude_target_dn /
                        (settings_.amplitude_dn_per_us_m2 * std::max(sorted_[k], 1e-9f));
  return static_cast<std::uint32_t>(std::clamp(wanted, 1.0, static_cast<double>(max_exposure_us)));
}

// Each pixel's own return in DN at this exposure.
void RawRenderer::gather_returns(const Scene& scene, double exposure_us) {
  const std::vector<float>& unit = caster_.unit_amplitude();
  const std::vector<std::int32_t>& surface = caster_.hit_surface();
  const float gain = static_cast<float>(settings_.amplitude_dn_per_us_m2 * exposure_us);
  const float inv_contrast = static_cast<float>(1.0 / settings_.modulation_contrast);
  const float ambient = static_cast<float>(settings_.ambient_dn_per_us * exposure_us);
  for (std::size_t i = 0; i < unit.size(); ++i) {
    amplitude_[i] = gain * unit[i];
    background_[i] = amplitude_[i] * inv_contrast;
    const std::int32_t s = surface[i];
    ambient_[i] =
        s >= 0
            ? ambient * static_cast<float>(scene.surfaces[static_cast<std::size_t>(s)].reflectivity)
            : 0.0f;
  }
}

// Where the edges between neighbouring pixels lie. A pixel's light comes
// from its own area (the lens blurs far less than a pixel: its diffraction
// spot is a fifth of the pitch), so on one surface its centre ray stands
// for it. Between two pixels that see different surfaces (or one surface
// folding out of sight) the edge lies at a distance t, uniform in 0..1
// pixel, from the first pixel's centre: the part of the first pixel past
// it, max(0, 0.5 - t), sees the second's surface, and the part of the
// second short of it, max(0, t - 0.5), sees the first's. Half the edge
// pixels are so pure, the other half mixed by up to half (those the
// processing's unwrapping and flying-pixel tests are there to catch).
void RawRenderer::find_edges(std::uint64_t stream_seed) {
  const CameraIntrinsics& cam = caster_.camera();
  const int w = static_cast<int>(cam.width), h = static_cast<int>(cam.height);
  const std::vector<float>& range = caster_.true_range_m();
  const std::vector<std::int32_t>& surface = caster_.hit_surface();
  // Only the last frame's edge pixels have shares to clear.
  for (std::size_t k = 0; k < edge_count_; ++k) {
    const std::int32_t i = edge_pixels_[k];
    for (std::vector<float>& e : edge_share_) e[static_cast<std::size_t>(i)] = 0.0f;
    on_edge_[static_cast<std::size_t>(i)] = 0;
  }
  edge_count_ = 0;
  if (!settings_.footprint_edges) return;
  constexpr float kFoldM = 0.02f;
  SimRandom rng(stream_seed);
  // One surface has an edge only where it folds out of sight: a jump of
  // 2 cm or more that stands out, three times, from the jumps on either
  // side (a steep smooth surface has them all alike). `before` and `after`
  // are the pixels beyond i and j on the same line (i, j themselves at the
  // border).
  auto folds = [&](int before, int i, int j, int after) {
    const float jump = std::fabs(range[i] - range[j]);
    if (jump < kFoldM) return false;
    const float side =
        std::min(std::fabs(range[before] - range[i]), std::fabs(range[j] - range[after]));
    return jump > 3.0f * side;
  };
  auto pair = [&](int i, int j, int i_side, int j_side, int before, int after) {
    if (surface[i] == surface[j] && !folds(before, i, j, after)) return;
    const float t = static_cast<float>(rng.uniform());
    edge_share_[i_side][i] = std::max(0.0f, 0.5f - t);
    edge_share_[j_side][j] = std::max(0.0f, t - 0.5f);
    for (int p : {i, j}) {
      if (on_edge_[static_cast<std::size_t>(p)]) continue;
      on_edge_[static_cast<std::size_t>(p)] = 1;
      edge_pixels_[edge_count_++] = p;
    }
  };
  enum { kUp, kDown, kLeft, kRight };
  for (int row = 0; row < h; ++row) {
    for (int col = 0; col < w; ++col) {
      const int i = row * w + col;
      if (col + 1 < w)
        pair(i, i + 1, kRight, kLeft, col > 0 ? i - 1 : i, col + 2 < w ? i + 2 : i + 1);
      if (row + 1 < h)
        pair(i, i + w, kDown, kUp, row > 0 ? i - w : i, row + 2 < h ? i + 2 * w : i + w);
    }
  }
  // A feature narrower than a pixel can take in more than its area from
  // both sides: the shares are then scaled to fill it.
  for (std::size_t k = 0; k < edge_count_; ++k) {
    const std::size_t i = static_cast<std::size_t>(edge_pixels_[k]);
    float total = 0.0f;
    for (const std::vector<float>& e : edge_share_) total += e[i];
    if (total <= 1.0f) continue;
    for (std::vector<float>& e : edge_share_) e[i] /= total;
  }
}

// The light arriving at each pixel for one frequency, as a phasor: its own
// return, with the parts of its area that see a neighbour's surface
// (find_edges) taking that neighbour's return instead.
void RawRenderer::form_phasors(int frequency, double temperature_offset_m) {
  const CameraIntrinsics& cam = caster_.camera();
  const int w = static_cast<int>(cam.width), h = static_cast<int>(cam.height);
  const std::vector<float>& range = caster_.true_range_m();
  const double k = phase_per_m(calibration_.frequency[frequency].frequency_hz);
  for (std::size_t i = 0; i < range.size(); ++i) {
    const float phase = static_cast<float>(k * range[i]);
    own_re_[i] = amplitude_[i] * std::cos(phase);
    own_im_[i] = amplitude_[i] * std::sin(phase);
  }
  // Off the edges a pixel's light is its own return; on them, mixed.
  std::copy(own_re_.begin(), own_re_.end(), sum_re_.begin());
  std::copy(own_im_.begin(), own_im_.end(), sum_im_.begin());
  std::copy(background_.begin(), background_.end(), sum_background_.begin());
  for (std::size_t e = 0; e < edge_count_; ++e) {
    const int i = edge_pixels_[e];
    const int row = i / w, col = i % w;
    const int nb[4] = {row > 0 ? i - w : i, row < h - 1 ? i + w : i, col > 0 ? i - 1 : i,
                       col < w - 1 ? i + 1 : i};
    float own = 1.0f, re = 0.0f, im = 0.0f, bg = 0.0f;
    for (int side = 0; side < 4; ++side) {
      const float share = edge_share_[side][static_cast<std::size_t>(i)];
      if (share <= 0.0f) continue;
      const std::size_t j = static_cast<std::size_t>(nb[side]);
      own -= share;
      re += share * own_re_[j];
      im += share * own_im_[j];
      bg += share * background_[j];
    }
    const std::size_t u = static_cast<std::size_t>(i);
    sum_re_[u] = re + own * own_re_[u];
    sum_im_[u] = im + own * own_im_[u];
    sum_background_[u] = bg + own * background_[u];
  }
  if (settings_.multipath) {
    for (std::size_t i = 0; i < range.size(); ++i) {
      const float a = multipath_amplitude_[i];
      if (a <= 0.0f) continue;
      const float phase = static_cast<float>(k * multipath_path_m_[i]);
      sum_re_[i] += a * std::cos(phase);
      sum_im_[i] += a * std::sin(phase);
      sum_background_[i] += a / static_cast<float>(settings_.modulation_contrast);
    }
  }
  // The pixel's own electronics: its fixed pattern, the frequency's offset
  // and the temperature drift turn the arriving phasor.
  const float drift = static_cast<float>(k * temperature_offset_m);
  const float dc = std::cos(drift), ds = std::sin(drift);
  for (std::size_t i = 0; i < range.size(); ++i) {
    const float c = fixed_cos_[frequency][i] * dc - fixed_sin_[frequency][i] * ds;
    const float s = fixed_sin_[frequency][i] * dc + fixed_cos_[frequency][i] * ds;
    const float re = sum_re_[i] * c - sum_im_[i] * s, im = sum_im_[i] * c + sum_re_[i] * s;
    sum_re_[i] = re;
    sum_im_[i] = im;
  }
}

// Light that reached this pixel's surface by way of a nearer one close by
// (a handrail's leg, a box on the wall): for each of eight ring samples 1
// to 15 cm nearer, a return along camera -> sample's point -> this point
// -> camera, of the sample's amplitude times the gain / 8. The samples'
// returns are merged into one of their total amplitude at their
// amplitude-weighted mean path (their paths differ by centimetres, a small
// part of a wavelength), so each frequency adds one phasor.
void RawRenderer::find_multipath() {
  const CameraIntrinsics& cam = caster_.camera();
  const int w = static_cast<int>(cam.width), h = static_cast<int>(cam.height);
  const int ring = settings_.multipath_ring_px;
  const std::vector<float>& range = caster_.true_range_m();
  const std::vector<Eigen::Vector3f>& rays = caster_.rays();
  const float share = static_cast<float>(settings_.multipath_gain / 8.0);
  const int dr[8] = {-1, -1, -1, 0, 0, 1, 1, 1}, dc[8] = {-1, 0, 1, -1, 1, -1, 0, 1};
  auto one_pixel = [&](int row, int col) {
    const std::size_t i = static_cast<std::size_t>(row * w + col);
    const float r = range[i];
    float total = 0.0f, weighted_path = 0.0f;
    for (int s = 0; s < 8 && r > 0.0f; ++s) {
      const int rr = row + dr[s] * ring, cc = col + dc[s] * ring;
      if (rr < 0 || cc < 0 || rr >= h || cc >= w) continue;
      const std::size_t j = static_cast<std::size_t>(rr * w + cc);
      const float rj = range[j];
      if (!(rj > r - 0.15f && rj < r - 0.01f)) continue;  // fails for no hit (0)
      const float between = (rays[i] * r - rays[j] * rj).norm();
      const float a = share * amplitude_[j];
      total += a;
      weighted_path += a * 0.5f * (rj + between + r);
    }
    multipath_amplitude_[i] = total;
    multipath_path_m_[i] = total > 0.0f ? weighted_path / total : 0.0f;
  };
  // Most pixels have no nearer surface on their ring: inside the image,
  // four at a time, the same test decides that first (the ring samples of
  // four neighbouring pixels are four neighbouring pixels too), and only
  // blocks with a candidate go pixel by pixel.
  typedef float Floats4 __attribute__((vector_size(16)));
  typedef std::int32_t Ints4 __attribute__((vector_size(16)));
  auto load4 = [&](std::size_t k) {
    Floats4 v;
    std::memcpy(&v, range.data() + k, sizeof v);
    return v;
  };
  for (int row = 0; row < h; ++row) {
    int col = 0;
    if (row >= ring && row < h - ring) {
      for (; col < ring; ++col) one_pixel(row, col);
      for (; col + 4 <= w - ring; col += 4) {
        const std::size_t i = static_cast<std::size_t>(row * w + col);
        const Floats4 r = load4(i), lo = r - 0.15f, hi = r - 0.01f;
        Ints4 any = {0, 0, 0, 0};
        for (int s = 0; s < 8; ++s) {
          const Floats4 rj =
              load4(static_cast<std::size_t>((row + dr[s] * ring) * w + col + dc[s] * ring));
          any |= (rj > lo) & (rj < hi);
        }
        if ((any[0] | any[1] | any[2] | any[3]) == 0) {
          for (int k = 0; k < 4; ++k) multipath_amplitude_[i + k] = multipath_path_m_[i + k] = 0.0f;
          continue;
        }
        for (int k = 0; k < 4; ++k) one_pixel(row, col + k);
      }
    }
    for (; col < w; ++col) one_pixel(row, col);
  }
}

void RawRenderer::render(const Scene& scene, const Eigen::Isometry3d& T_world_cam, tof::Mode mode,
                         std::uint32_t max_exposure_us, std::uint64_t seed,
                         std::uint64_t frame_index, tof::RawFrame* out) {
  caster_.cast(scene, T_world_cam);
  const std::uint32_t exposure_us = choose_exposure_us(max_exposure_us);
  gather_returns(scene, exposure_us);
  if (settings_.multipath) find_multipath();
  find_edges(mix_seed(seed, frame_index, 30));
  const double temperature_offset_m =
      calibration_.temperature_drift_m_per_k *
      (settings_.sensor_temperature_c - calibration_.reference_temperature_c);
  out->mode = mode;
  out->frame_id = frame_index;
  out->exposure_us = exposure_us;
  out->sensor_temperature_c = static_cast<float>(settings_.sensor_temperature_c);
  const int frequencies = std::min(tof::frequency_count(mode), calibration_.frequency_count);
  for (int f = 0; f < frequencies; ++f) {
    form_phasors(f, temperature_offset_m);
    write_samples(f, out, mix_seed(seed, frame_index, 20 + static_cast<std::uint64_t>(f)));
  }
  write_grey(out, mix_seed(seed, frame_index, 29));
}

}  // namespace sim_hal
