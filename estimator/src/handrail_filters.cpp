#include "estimator/handrail_filters.hpp"

#include "four_lanes.hpp"
#include "run_levels.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>

namespace estimator {
namespace {

struct Pixel {
  int row;
  int col;
};

// Row and column of pixel indices taken in ascending order (the order of
// every list the stages produce) without an integer division per pixel:
// the row only ever moves forward, at most `height` times per pass.
class AscendingPixels {
 public:
  explicit AscendingPixels(const OrganizedCloud& cloud) : width_(static_cast<int>(cloud.width)) {}
  Pixel operator()(std::int32_t i) {
    while (i >= row_start_ + width_) {
      ++row_;
      row_start_ += width_;
    }
    return {row_, i - row_start_};
  }

 private:
  int width_;
  int row_ = 0;
  std::int32_t row_start_ = 0;
};

using run_levels::clamp_noise;
using run_levels::level_beside_end;

// The cross test's probes for the wall beside a bar. A probe searches a
// segment of its row or column: from `offset` pixels out back toward the
// bar, but never nearer than half the offset (nearer, it could land on the
// bar itself). It finds the wall where two pixels in a row of the segment
// are clearly on it: not raised off the searched surface, and not within
// the gap window widened by the pixel's noise either (a far or grazing
// pixel of a surface at the bar's height can fall below the wall's
// tolerance; it is no evidence of the wall). Past the image's edge a pixel
// counts as wall (a bar near the edge has only its inner side in view), an
// invalid pixel does not. The search does not stop at the first thing it
// meets: on a rack wall the probe's spot often lies on a taller face or a
// rack's edge beside the track, with the gap or the face the track stands
// on between it and the bar. Two pixels, not one, because a noisy raised
// surface (a wall seen at grazing incidence) has single pixels scattered
// below its level.
//
// Along a row the wall pixels are a bitset (one bit per pixel, from the
// flags' wall and gap bits eight pixels at a time), and so are the pairs' first
// pixels: a probe tests a few words. Down the columns every pixel holds how
// many rows below it the first pair starts (one byte, saturated), filled
// for the whole image a row at a time from the bottom up, sixteen columns
// per vector operation.
class WallPairs {
 public:
  WallPairs(const OrganizedCloud& cloud, Workspace& ws)
      : flags_(ws.flags.get()),
        width_(static_cast<int>(cloud.width)),
        height_(static_cast<int>(cloud.height)),
        rows_down_(ws.column_wall_pair_rows_down.get()) {}

  // The probe from pixel (row, col) along its row, toward higher columns
  // (sign 1) or lower (-1), offset_px pixels out.
  bool along_row(int row, int col, int sign, int offset_px) {
    if (row != row_) fill_row(row);
    const int near = (offset_px + 1) / 2;
    // Toward higher columns the search runs from the far end down: a pair
    // (j, j + 1) with j in [lo, hi - 1], the row's last pixel pairing with
    // what lies past it.
    if (sign > 0) {
      const int lo = col + near, hi = std::min(col + offset_px - 1, width_ - 1);
      return lo <= hi && any_bit(row_pairs_, lo, hi);
    }
    // Toward lower columns it runs from the far end up: a pair (j - 1, j)
    // with j in [lo + 1, hi], pixel 0 pairing with what lies before it.
    const int lo = col - offset_px, hi = col - near;
    const int first = std::max(lo + 1, 0);
    if (first > hi) return false;
    if (first == 0 && (row_walls_[0] & 1u)) return true;
    const int from = std::max(first, 1) - 1;
    return from <= hi - 1 && any_bit(row_pairs_, from, hi - 1);
  }

  // The same down the pixel's column (sign 1: toward higher rows).
  bool along_column(int row, int col, int sign, int offset_px) {
    if (!columns_filled_) fill_columns();
    const int near = (offset_px + 1) / 2;
    if (sign > 0) {
      const int lo = row + near, hi = std::min(row + offset_px - 1, height_ - 1);
      return lo <= hi && column_pair_within(col, lo, hi);
    }
    const int lo = row - offset_px, hi = row - near;
    const int first = std::max(lo + 1, 0);
    if (first > hi) return false;
    if (first == 0 && clear_wall(flags_[col])) return true;
    const int from = std::max(first, 1) - 1;
    return from <= hi - 1 && column_pair_within(col, from, hi - 1);
  }

 private:
  static constexpr int kWords = static_cast<int>(Workspace::kMaxWidth / 64) + 1;
  static_assert(kFlagWall == 1u << 7 && kFlagGap == 1u << 2,
                "the gap bit shifts onto the wall bit");

  // The most rows_down_ holds: no pair starts within kFar - 1 rows below.
  static constexpr int kFar = 255;

  // Whether a pair starts in column col at a row in [lo, hi] (lo <= hi):
  // one lookup, unless a probe spans more rows than a byte counts (bounded
  // by the image's height / kFar steps).
  bool column_pair_within(int col, int lo, int hi) const {
    for (int r = lo; r <= hi; r += kFar) {
      const int rows = rows_down_[r * width_ + col];
      if (rows < kFar) return r + rows <= hi;
    }
    return false;
  }

  // On the wall and not in the gap window widened by the pixel's noise.
  static bool clear_wall(std::uint8_t f) { return (f & kFlagWall) && !(f & kFlagGap); }

  // Whether any bit in [a, b] (a <= b) is set.
  static bool any_bit(const std::uint64_t* bits, int a, int b) {
    const int wa = a >> 6, wb = b >> 6;
    const std::uint64_t low = ~0ull << (a & 63);
    const std::uint64_t high = ~0ull >> (63 - (b & 63));
    if (wa == wb) return (bits[wa] & low & high) != 0;
    if (bits[wa] & low) return true;
    for (int w = wa + 1; w < wb; ++w) {
      if (bits[w]) return true;
    }
    return (bits[wb] & high) != 0;
  }

  void fill_row(int row) {
    const std::uint8_t* f = flags_ + static_cast<std::size_t>(row) * width_;
    const int words = (width_ + 64) / 64;  // room for the bit past the end
    for (int w = 0; w < words; ++w) row_walls_[w] = 0;
    int c = 0;
    for (; c + 8 <= width_; c += 8) {
      // The wall bit (bit 7) of eight bytes gathered into one byte, pixel
      // c in its lowest bit (the bytes loaded little-endian, as on the host
      // and the BeagleBone).
      static_assert(__BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__, "pixel c is the lowest byte");
      std::uint64_t eight;
      std::memcpy(&eight, f + c, sizeof eight);
      const std::uint64_t clear = eight & ~(eight << 5);  // bit 2 (gap) onto bit 7 (wall)
      const std::uint64_t gathered =
          ((clear & 0x8080808080808080ull) >> 7) * 0x0102040810204080ull >> 56;
      row_walls_[c >> 6] |= gathered << (c & 63);
    }
    for (; c < width_; ++c) {
      if (clear_wall(f[c])) row_walls_[c >> 6] |= 1ull << (c & 63);
    }
    // Past the row's end counts as wall.
    row_walls_[width_ >> 6] |= 1ull << (width_ & 63);
    for (int w = 0; w < words; ++w) {
      const std::uint64_t next_word = w + 1 < words ? row_walls_[w + 1] : 0;
      row_pairs_[w] = row_walls_[w] & ((row_walls_[w] >> 1) | (next_word << 63));
    }
    row_ = row;
  }

  // rows_down_[r][c]: how many rows below r (0: r itself) the first row
  // r' >= r starts where pixels (r', c) and (r' + 1, c) are both wall, the
  // last row pairing with what lies below the image; height_ - r if none,
  // and at most kFar.
  void fill_columns() {
    typedef std::uint8_t Bytes16 __attribute__((vector_size(16)));
    typedef std::int8_t SignedBytes16 __attribute__((vector_size(16)));
    const int last = height_ - 1;
    std::uint8_t* bottom = rows_down_ + static_cast<std::size_t>(last) * width_;
    const std::uint8_t* f = flags_ + static_cast<std::size_t>(last) * width_;
    for (int c = 0; c < width_; ++c) bottom[c] = clear_wall(f[c]) ? 0 : 1;
    for (int r = last - 1; r >= 0; --r) {
      std::uint8_t* down = rows_down_ + static_cast<std::size_t>(r) * width_;
      const std::uint8_t* below = down + width_;
      const std::uint8_t* here = flags_ + static_cast<std::size_t>(r) * width_;
      const std::uint8_t* under = here + width_;
      int c = 0;
      for (; c + 16 <= width_; c += 16) {
        // The pair test on 64-bit words, eight bytes each: a vector of
        // bytes has no shift on SSE2, and the compiler would shift them
        // one by one. Shifted by 5, each byte's gap bit lands on its own
        // wall bit (bit 7, the byte's sign).
        std::uint64_t a[2], b[2], pair_words[2];
        std::memcpy(a, here + c, sizeof a);
        std::memcpy(b, under + c, sizeof b);
        for (int h = 0; h < 2; ++h) pair_words[h] = a[h] & b[h] & ~((a[h] | b[h]) << 5);
        SignedBytes16 pairs;
        Bytes16 rows_below;
        std::memcpy(&pairs, pair_words, sizeof pairs);
        std::memcpy(&rows_below, below + c, sizeof rows_below);
        const SignedBytes16 zero = {};
        const Bytes16 starts_here = reinterpret_cast<Bytes16>(pairs < zero);
        // One row further than below's, held at kFar.
        const Bytes16 not_far = reinterpret_cast<Bytes16>(rows_below != kFar);
        const Bytes16 rows = (rows_below - not_far) & ~starts_here;
        std::memcpy(down + c, &rows, sizeof rows);
      }
      for (; c < width_; ++c) {
        const int further = below[c] < kFar ? below[c] + 1 : kFar;
        down[c] =
            clear_wall(here[c]) && clear_wall(under[c]) ? 0 : static_cast<std::uint8_t>(further);
      }
    }
    columns_filled_ = true;
  }

  const std::uint8_t* flags_;
  int width_, height_;
  std::uint8_t* rows_down_;
  std::uint64_t row_walls_[kWords];
  std::uint64_t row_pairs_[kWords];
  int row_ = -1;
  bool columns_filled_ = false;
};

struct RaisedRun {
  float width_m = -1.0f;  // < 0: the run leaves the image, width unknown
  float peak_m = 0.0f;    // its highest point's distance from the wall
  // The surface it stands out from: the higher of the two levels just
  // outside its ends (NaN: neither side shows one).
  float base_m = NAN;
  int first = 0;  // its first and last pixel along the walk
  int last = -1;
};

// An invalid pixel's wall distance is -infinity: one load and one
// comparison judge it.
bool is_raised(const Workspace& ws, std::int32_t i, float raised_min_m) {
  return ws.signed_distance_m[i] >= raised_min_m;
}

// The whole raised run through pixel `k` of a line of `n` pixels starting
// at `base` with stride `stride` (a row or a column): the 3-D distance
// between its two outermost raised pixels, plus one pixel's footprint since
// each outermost pixel centre lies half a pixel inside the silhouette; and
// its highest point above the wall. A run that reaches the image's edge has
// no known width. Measured once per run (every pixel of a run shares it),
// in one walk each way that also finds the peak.
RaisedRun measure_raised_run(const OrganizedCloud& cloud, const Workspace& ws, std::int32_t base,
                             int stride, int n, int k, float raised_min_m, float pixel_angle) {
  const float* distance_m = ws.signed_distance_m.get() + base;
  RaisedRun run;
  // Pixel k itself may sit below the raised height (let into the gap set
  // by its noise); it belongs to its run all the same.
  run.peak_m = std::max(0.0f, distance_m[k * stride]);
  run.first = k;
  while (run.first > 0) {
    const float s = distance_m[(run.first - 1) * stride];
    if (!(s >= raised_min_m)) break;
    run.peak_m = std::max(run.peak_m, s);
    --run.first;
  }
  run.last = k;
  while (run.last < n - 1) {
    const float s = distance_m[(run.last + 1) * stride];
    if (!(s >= raised_min_m)) break;
    run.peak_m = std::max(run.peak_m, s);
    ++run.last;
  }
  if (run.first == 0 || run.last == n - 1) return run;
  // fmax of NaN and a number is the number: one side's level will do.
  run.base_m = std::fmax(level_beside_end(distance_m, stride, n, run.first, -1),
                         level_beside_end(distance_m, stride, n, run.last, 1));
  const CloudPoint& a = cloud.points[base + run.first * stride];
  const CloudPoint& b = cloud.points[base + run.last * stride];
  const float dx = a.x_m - b.x_m, dy = a.y_m - b.y_m, dz = a.z_m - b.z_m;
  const float footprint_m = 0.5f * (a.z_m + b.z_m) * pixel_angle;
  run.width_m = std::sqrt(dx * dx + dy * dy + dz * dz) + footprint_m;
  return run;
}

// The raised runs through pixels taken in ascending order: the row's run
// is remembered until the walk leaves it, and each column remembers its
// last run, so every run is measured once per pass.
class RunCache {
 public:
  RunCache(const OrganizedCloud& cloud, const DetectorConfig& cfg, const PixelScale& scale,
           Workspace& ws)
      : cloud_(cloud),
        ws_(ws),
        w_(static_cast<int>(cloud.width)),
        rows_(static_cast<int>(cloud.height)),
        raised_min_(gap_min_m(cfg)),
        inv_fx_(1.0f / scale.fx_px),
        inv_fy_(1.0f / scale.fy_px) {
    for (int c = 0; c < w_; ++c) ws_.column_run_last[c] = -1;
  }
  // A pixel below the raised height (let into the gap set by its noise)
  // joins the raised runs either side of it: such a run is its own and is
  // not remembered, so that no other pixel's verdict depends on the order
  // of the walk.
  const RaisedRun& row(Pixel q) {
    if (!is_raised(ws_, q.row * w_ + q.col, raised_min_)) {
      own_run_ = measure_raised_run(cloud_, ws_, q.row * w_, 1, w_, q.col, raised_min_, inv_fx_);
      return own_run_;
    }
    if (q.row != row_run_row_ || q.col < row_run_.first || q.col > row_run_.last) {
      row_run_ = measure_raised_run(cloud_, ws_, q.row * w_, 1, w_, q.col, raised_min_, inv_fx_);
      row_run_row_ = q.row;
    }
    return row_run_;
  }
  // Width, peak and (when asked) base of the column run through q.
  void column(Pixel q, float* width_m, float* peak_m, float* base_m = nullptr) {
    const int c = q.col;
    if (!is_raised(ws_, q.row * w_ + c, raised_min_)) {
      const RaisedRun run =
          measure_raised_run(cloud_, ws_, c, w_, rows_, q.row, raised_min_, inv_fy_);
      *width_m = run.width_m;
      *peak_m = run.peak_m;
      if (base_m) *base_m = run.base_m;
      return;
    }
    if (q.row < ws_.column_run_first[c] || q.row > ws_.column_run_last[c]) {
      const RaisedRun run =
          measure_raised_run(cloud_, ws_, c, w_, rows_, q.row, raised_min_, inv_fy_);
      ws_.column_run_first[c] = run.first;
      ws_.column_run_last[c] = run.last;
      ws_.column_run_width_m[c] = run.width_m;
      ws_.column_run_peak_m[c] = run.peak_m;
      ws_.column_run_base_m[c] = run.base_m;
    }
    *width_m = ws_.column_run_width_m[c];
    *peak_m = ws_.column_run_peak_m[c];
    if (base_m) *base_m = ws_.column_run_base_m[c];
  }

 private:
  const OrganizedCloud& cloud_;
  Workspace& ws_;
  int w_, rows_;
  float raised_min_, inv_fx_, inv_fy_;
  RaisedRun row_run_, own_run_;
  int row_run_row_ = -1;
};

}  // namespace

void cross_point_test(const OrganizedCloud& cloud, const DetectorConfig& cfg, const Plane& wall,
                      const PixelScale& scale, Workspace& ws) {
  const float d_c = cross_distance_m(cfg);
  const float l_h = cfg.handrail.bar_center_offset_m - 0.5f * cfg.handrail.bar_depth_m;
  const float nz = std::fmax(std::fabs(wall.normal.z()), 1e-3f);
  const float theta = std::atan(wall.normal.x() / nz);
  const float phi = std::atan(wall.normal.y() / nz);
  // Eq. 2: metric probe distances, widened on the side where the legs
  // appear when the wall is tilted.
  const float x_plus = std::fmax(d_c * std::cos(theta) - (l_h + d_c) * std::sin(theta), d_c);
  const float x_minus = std::fmax(d_c * std::cos(theta) + (l_h + d_c) * std::sin(theta), d_c);
  const float y_plus = std::fmax(d_c * std::cos(phi) - (l_h + d_c) * std::sin(phi), d_c);
  const float y_minus = std::fmax(d_c * std::cos(phi) + (l_h + d_c) * std::sin(phi), d_c);

  // Offsets in pixels are (focal length * metres) / depth: one division per
  // pixel.
  const float fx_plus = scale.fx_px * x_plus, fx_minus = scale.fx_px * x_minus;
  const float fy_plus = scale.fy_px * y_plus, fy_minus = scale.fy_px * y_minus;
  const float fx_plain = scale.fx_px * d_c, fy_plain = scale.fy_px * d_c;
  const int width = static_cast<int>(cloud.width), height = static_cast<int>(cloud.height);
  // The probes are skipped where the raised run through the pixel in that
  // direction is already outside the side width test's range: that test
  // would reject the pixel whatever the probes found, and on a frame full
  // of instruments most raised pixels are such.
  const HandrailGeometry& h = cfg.handrail;
  const float width_min = cfg.side_width_min_ratio * h.bar_width_m;
  const float width_max = cfg.side_width_max_ratio * std::fmax(h.bar_width_m, h.bar_depth_m);
  auto plausible = [&](float width_m) { return width_m > width_min && width_m < width_max; };
  RunCache runs(cloud, cfg, scale, ws);
  WallPairs walls(cloud, ws);
  ws.cross.clear();
  AscendingPixels pixel_of(cloud);
  const float* inverse_depth = ws.inverse_depth_per_m.get();
  const four_lanes::Floats4 focal_times_probe_m = {fx_plus, fx_minus, fy_plus, fy_minus};
  for (std::int32_t i : ws.gap) {
    const Pixel q = pixel_of(i);
    // The four probes' offsets in pixels, rounded to the nearest integer
    // (half away from zero), in one vector.
    const four_lanes::Floats4 offsets = focal_times_probe_m * inverse_depth[i];
    const four_lanes::Floats4 zero = {0.0f, 0.0f, 0.0f, 0.0f};
    const four_lanes::Floats4 half = {0.5f, 0.5f, 0.5f, 0.5f};
    const four_lanes::Ints4 offset_px =
        __builtin_convertvector(offsets + (offsets < zero ? -half : half), four_lanes::Ints4);
    // The probes first, each a lookup; a run's width may need a walk down
    // a column.
    // A widened probe whose whole segment lies past the image's edge
    // searches at the plain distance instead: the widening is for the legs,
    // and between the bar and the edge the wall may still show.
    const float plain_x = fx_plain * inverse_depth[i], plain_y = fy_plain * inverse_depth[i];
    auto within_view = [](int pos, int sign, int offset, int extent, float plain_px) {
      const int near = (offset + 1) / 2;
      const bool past = sign > 0 ? pos + near >= extent : pos - near < 0;
      return past ? static_cast<int>(plain_px + 0.5f) : offset;
    };
    const bool x_ok =
        walls.along_row(q.row, q.col, 1, within_view(q.col, 1, offset_px[0], width, plain_x)) &&
        walls.along_row(q.row, q.col, -1, within_view(q.col, -1, offset_px[1], width, plain_x)) &&
        plausible(runs.row(q).width_m);
    bool y_ok =
        walls.along_column(q.row, q.col, 1, within_view(q.row, 1, offset_px[2], height, plain_y)) &&
        walls.along_column(q.row, q.col, -1, within_view(q.row, -1, offset_px[3], height, plain_y));
    if (y_ok) {
      float column_width = 0.0f, column_peak = 0.0f;
      runs.column(q, &column_width, &column_peak);
      y_ok = plausible(column_width);
    }
    if (x_ok) ws.flags[i] |= kFlagCrossX;
    if (y_ok) ws.flags[i] |= kFlagCrossY;
    if (x_ok || y_ok) ws.cross.push(i);
  }
}

void side_width_test(const OrganizedCloud& cloud, const DetectorConfig& cfg,
                     const PixelScale& scale, Workspace& ws, FrontFace front_face) {
  const HandrailGeometry& h = cfg.handrail;
  const float width_min = cfg.side_width_min_ratio * h.bar_width_m;
  const float width_max = cfg.side_width_max_ratio * std::fmax(h.bar_width_m, h.bar_depth_m);
  const float front = h.bar_center_offset_m + 0.5f * h.bar_depth_m;
  RunCache runs(cloud, cfg, scale, ws);
  ws.side.clear();
  AscendingPixels pixel_of(cloud);
  for (std::int32_t i : ws.cross) {
    const Pixel q = pixel_of(i);
    // The run's peak is the bar's front face (or a round bar's crown); a
    // cable or pipe of similar width at another height fails here. Noise
    // lifts the highest of a few samples, hence the pixel's sigma.
    const float peak_tolerance =
        cfg.run_peak_tolerance_m + 2.0f * clamp_noise(cloud.points[i].noise_m);
    // A bar on a deeper face has its front lower by that face's depth, and
    // that face (or the seat track on it) is beside it: its front stands a
    // handrail's height above what it stands out from. A cable as low over
    // the searched surface has that surface beside it. The face must be
    // deeper than the window above allows for (a bar on a face up to about
    // a centimetre deeper passes it already), so that noise on the surface
    // beside the run does not make one.
    auto front_passes = [&](float peak_m, float base_m) {
      if (std::fabs(peak_m - front) < peak_tolerance) return true;
      if (front_face != FrontFace::kOnSearchedOrDeeper || !(base_m < -peak_tolerance)) {
        return false;
      }
      const float rise_m = peak_m - base_m;
      return rise_m > front - peak_tolerance && rise_m < front + cfg.mount_step_m + peak_tolerance;
    };
    auto passes = [&](float width_m, float peak_m, float base_m) {
      return width_m > width_min && width_m < width_max && front_passes(peak_m, base_m);
    };
    bool pass = false;
    if (ws.flags[i] & kFlagCrossX) {
      const RaisedRun& run = runs.row(q);
      pass = passes(run.width_m, run.peak_m, run.base_m);
    }
    if (!pass && (ws.flags[i] & kFlagCrossY)) {
      float width = 0.0f, peak = 0.0f, base = 0.0f;
      runs.column(q, &width, &peak, &base);
      pass = passes(width, peak, base);
    }
    if (pass) {
      ws.flags[i] |= kFlagSide;
      ws.side.push(i);
    }
  }
}

}  // namespace estimator
