// The gap distance test (eq. 1), the detector's one pass over every pixel.
// It is the frame's largest cost after the cloud has been streamed in, so
// it works on four pixels at a time with the compiler's portable 128-bit
// vectors (SSE2 on the host, NEON on the BeagleBone's Cortex-A8): the
// same source, no intrinsics, and the last few pixels as a block padded
// with invalid points. Values move between a point's fields and a vector's
// lanes by 4 x 4 transposes (shuffles), not lane by lane.
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <limits>

#include "estimator/handrail_filters.hpp"
#include "four_lanes.hpp"

namespace estimator {
namespace {

using four_lanes::Floats4;
using four_lanes::Ints4;
using four_lanes::load_four_points;
typedef std::uint8_t Bytes4 __attribute__((vector_size(4)));

// The most faces in view a search takes as the probes' wall.
constexpr std::uint32_t kMaxWallFaces = 8;

// What the pass needs of the wall and the configuration, once per frame.
struct GapTestLimits {
  float nx, ny, nz, d;
  float min_range_m, max_range_m;
  float gap_lo_m, gap_hi_m;  // eq. 1's window on the signed wall distance
  float plane_inlier_m, wall_tolerance_m;
  // Faces in view that are the probes' wall on this mount (distances from
  // the dominant plane; see gap_distance_shifted).
  std::uint32_t face_count;
  float face_m[kMaxWallFaces];
};

// A face in view is the probes' wall on the mount offset_m from the
// dominant plane when it stands above the wall tolerance over the mount
// (below it, its pixels are wall anyway) and below the gap window.
bool face_is_wall(const DetectorConfig& cfg, float face_m, float offset_m) {
  const float over_mount_m = face_m - offset_m;
  return over_mount_m >= cfg.wall_tolerance_m && over_mount_m < gap_min_m(cfg);
}

// A pixel is on a face within this much plus its own noise (half the gap
// window's widening, one sigma): faces in view are histogram peaks refined
// to their mean, and neighbouring faces differ by a centimetre or more.
constexpr float kOnFaceM = 0.005f;

// Four pixels' flags and wall distances. Lanes are all-ones where a
// comparison holds, so a flag is its lane masked with the flag's bit.
// Validity is is_usable_point() in fewer steps: a NaN or infinite
// coordinate makes s NaN (s == s fails), and the range test (min_range > 0)
// rejects a NaN, infinite or non-positive z. A noisy pixel's gap window is
// widened by twice its standard deviation, the noise bounded to [0, 2 cm]
// with NaN as 0, so no bad value can open the windows.
inline __attribute__((always_inline)) Ints4 classify_four_pixels(const CloudPoint* p,
                                                                 const GapTestLimits& g,
                                                                 float* distance_m, float* widen_m,
                                                                 float* inverse_depth_per_m) {
  Floats4 x, y, z, noise;
  load_four_points(p, &x, &y, &z, &noise);
  const Ints4 confidence = {p[0].confidence, p[1].confidence, p[2].confidence, p[3].confidence};
  const Floats4 s = g.nx * x + g.ny * y + g.nz * z + g.d;
  const Ints4 valid = (confidence != 0) & (z >= g.min_range_m) & (z <= g.max_range_m) & (s == s);
  const Floats4 zero = {0.0f, 0.0f, 0.0f, 0.0f};
  const Floats4 below_all = zero - std::numeric_limits<float>::infinity();
  const Floats4 distance = valid ? s : below_all;
  std::memcpy(distance_m, &distance, sizeof distance);   // one unaligned vector store
  const Floats4 positive = noise > zero ? noise : zero;  // NaN fails: 0
  const Floats4 cap = {0.02f, 0.02f, 0.02f, 0.02f};
  const Floats4 widen = 2.0f * (positive < cap ? positive : cap);
  std::memcpy(widen_m, &widen, sizeof widen);
  const Floats4 inverse_depth = 1.0f / z;  // exactly rounded, as the scalar division
  std::memcpy(inverse_depth_per_m, &inverse_depth, sizeof inverse_depth);
  const Floats4 abs_s = s < zero ? -s : s;
  const Ints4 on_plane = valid & (abs_s < g.plane_inlier_m);
  // "On the wall" for the cross test's probes means not raised off it: a
  // probe beside a bar on a rack wall lands on a face below the bar's seat
  // track, or in a gap between racks, as often as on the mount surface.
  const Ints4 on_wall = valid & (s < g.wall_tolerance_m);
  const Ints4 in_gap = valid & (s >= g.gap_lo_m - widen) & (s <= g.gap_hi_m + widen);
  constexpr std::int32_t kValid = kFlagValid, kPlane = kFlagPlane, kGap = kFlagGap,
                         kWall = kFlagWall;  // the enum as the lanes' type
  return (valid & kValid) | (on_plane & kPlane) | (in_gap & kGap) | (on_wall & kWall);
}

// Four pixels of the shifted pass: the dominant plane's distance s0
// (-infinity where invalid, which every comparison below but "valid" keeps
// so) moved by the mount's offset.
inline __attribute__((always_inline)) Ints4 classify_four_shifted(const float* plane_distance_m,
                                                                  const float* widen_m,
                                                                  const GapTestLimits& g,
                                                                  float offset_m,
                                                                  float* distance_m) {
  Floats4 s0, widen;
  std::memcpy(&s0, plane_distance_m, sizeof s0);
  std::memcpy(&widen, widen_m, sizeof widen);
  const Floats4 s = s0 - offset_m;
  std::memcpy(distance_m, &s, sizeof s);
  const Floats4 zero = {0.0f, 0.0f, 0.0f, 0.0f};
  const Ints4 valid = s0 > zero - std::numeric_limits<float>::infinity();
  const Floats4 abs_s0 = s0 < zero ? -s0 : s0;
  const Ints4 on_plane = valid & (abs_s0 < g.plane_inlier_m);
  const Ints4 in_gap = valid & (s >= g.gap_lo_m - widen) & (s <= g.gap_hi_m + widen);
  Ints4 on_face = {0, 0, 0, 0};
  const Floats4 face_tolerance = kOnFaceM + 0.5f * widen;
  for (std::uint32_t k = 0; k < g.face_count; ++k) {
    const Floats4 off_face = s0 - g.face_m[k];
    on_face |= (off_face <= face_tolerance) & (off_face >= zero - face_tolerance);
  }
  const Ints4 on_wall = valid & ((s < g.wall_tolerance_m) | (on_face & (s < g.gap_lo_m - widen)));
  constexpr std::int32_t kValid = kFlagValid, kPlane = kFlagPlane, kGap = kFlagGap,
                         kWall = kFlagWall;
  return (valid & kValid) | (on_plane & kPlane) | (in_gap & kGap) | (on_wall & kWall);
}

// Sixteen pixels' flags (four blocks of four, each lane 0 to 255) stored
// as sixteen bytes in pixel order. Converting a vector of four ints to four
// bytes lane by lane is scalar code on SSE2; instead the four blocks are
// transposed, so that vector B holds byte B of every 32-bit word of the
// result, and shifted into place.
Ints4 store_flag_bytes(const Ints4 flags[4], std::uint8_t* out) {
  const Ints4 ab_low = __builtin_shuffle(flags[0], flags[1], Ints4{0, 4, 1, 5});
  const Ints4 ab_high = __builtin_shuffle(flags[0], flags[1], Ints4{2, 6, 3, 7});
  const Ints4 cd_low = __builtin_shuffle(flags[2], flags[3], Ints4{0, 4, 1, 5});
  const Ints4 cd_high = __builtin_shuffle(flags[2], flags[3], Ints4{2, 6, 3, 7});
  const Ints4 byte0 = __builtin_shuffle(ab_low, cd_low, Ints4{0, 1, 4, 5});
  const Ints4 byte1 = __builtin_shuffle(ab_low, cd_low, Ints4{2, 3, 6, 7});
  const Ints4 byte2 = __builtin_shuffle(ab_high, cd_high, Ints4{0, 1, 4, 5});
  const Ints4 byte3 = __builtin_shuffle(ab_high, cd_high, Ints4{2, 3, 6, 7});
  const Ints4 words = byte0 | (byte1 << 8) | (byte2 << 16) | (byte3 << 24);
  static_assert(__BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__, "byte 0 of a word is its first pixel");
  std::memcpy(out, &words, sizeof words);
  return words;
}

// Bit 0 of each of eight bytes gathered into one byte, byte i into bit i
// (each byte's bit lands in the product's top byte exactly once, with no
// carries between them).
std::uint32_t gather_low_bits(std::uint64_t eight_bytes) {
  return static_cast<std::uint32_t>(
      ((eight_bytes & 0x0101010101010101ull) * 0x0102040810204080ull) >> 56);
}

// How many of eight bytes have bit 0 set (their sum, at most 8, lands in
// the product's top byte).
std::uint32_t count_low_bits(std::uint64_t eight_bytes) {
  return static_cast<std::uint32_t>(
      ((eight_bytes & 0x0101010101010101ull) * 0x0101010101010101ull) >> 56);
}

// The gap list's entries for four pixels from their four mask bits: the
// lanes of the set bits, in order, as one vector (the rest don't care), and
// how many there are. All four slots are written and the count moves on by
// the bits set, so there is no branch per pixel.
struct LaneList {
  Ints4 lanes;
  std::int32_t count;
};
constexpr LaneList kSetLanes[16] = {
    {{0, 0, 0, 0}, 0}, {{0, 0, 0, 0}, 1}, {{1, 0, 0, 0}, 1}, {{0, 1, 0, 0}, 2},
    {{2, 0, 0, 0}, 1}, {{0, 2, 0, 0}, 2}, {{1, 2, 0, 0}, 2}, {{0, 1, 2, 0}, 3},
    {{3, 0, 0, 0}, 1}, {{0, 3, 0, 0}, 2}, {{1, 3, 0, 0}, 2}, {{0, 1, 3, 0}, 3},
    {{2, 3, 0, 0}, 2}, {{0, 2, 3, 0}, 3}, {{1, 2, 3, 0}, 3}, {{0, 1, 2, 3}, 4},
};

// The pass over every pixel, in blocks of sixteen (four vectors, their
// flags stored with one vector store), then of four: `block(k)` classifies
// pixels k..k+3 (writing their distances), `tail(k, rest)` the last one to
// three, padded with invalid pixels (writing only the real ones' distances).
// Here the flags are stored, the lanes counted and the gap list built; with
// `plane_left_out` a pixel on the plane keeps its gap bit but is left out of
// the list.
//
// Invalid pixels are scattered over a ToF frame, so the gap list is built
// without a branch per pixel: slots are written whether or not the pixel
// belongs, and the count advances only by those that do (the list has a
// slot per pixel). The outputs are locals: byte stores through a member
// could alias anything and force reloads.
template <class Block, class Tail>
std::uint32_t run_gap_pass(std::size_t n, Workspace& ws, std::uint32_t* valid_pixels, Block block,
                           Tail tail, bool plane_left_out) {
  std::uint8_t* flags_out = ws.flags.get();
  std::int32_t* gap_out = ws.gap.begin();
  std::size_t valid_count = 0, gap_count = 0, plane_inliers = 0;
  // Lane-wise counts (a true lane is -1, so subtracting counts it); a block
  // of four is at most 4 per lane, so 2^31 / 4 pixels cannot overflow.
  Ints4 valid_lanes = {0, 0, 0, 0}, plane_lanes = {0, 0, 0, 0};
  constexpr std::int32_t kValid = kFlagValid, kPlane = kFlagPlane, kGap = kFlagGap;
  const std::int32_t list_skips = plane_left_out ? kPlane : 0;
  std::size_t k = 0;
  for (; k + 16 <= n; k += 16) {
    const Ints4 flags[4] = {block(k), block(k + 4), block(k + 8), block(k + 12)};
    const Ints4 flag_bytes = store_flag_bytes(flags, flags_out + k);
    // The counts and the list's mask from the packed bytes, eight pixels
    // to a 64-bit word.
    std::uint64_t half[2];
    std::memcpy(half, &flag_bytes, sizeof half);
    std::uint32_t mask = 0;
    for (int h = 0; h < 2; ++h) {
      static_assert(kFlagValid == 1u && kFlagPlane == 1u << 1 && kFlagGap == 1u << 2,
                    "the valid, plane and gap bits shifted to bit 0");
      valid_count += count_low_bits(half[h]);
      plane_inliers += count_low_bits(half[h] >> 1);
      const std::uint64_t listed = (half[h] >> 2) & ~(plane_left_out ? half[h] >> 1 : 0ull);
      mask |= gather_low_bits(listed) << (8 * h);
    }
    if (mask == 0) continue;
    // Four slots written from gap_count on, which stays at most k + 4 v:
    // within the block's own slots of the list (one per pixel).
    for (int v = 0; v < 4; ++v) {
      const LaneList& set = kSetLanes[(mask >> (4 * v)) & 15u];
      const Ints4 entries = set.lanes + static_cast<std::int32_t>(k + 4 * v);
      std::memcpy(gap_out + gap_count, &entries, sizeof entries);
      gap_count += static_cast<std::size_t>(set.count);
    }
  }
  for (; k + 4 <= n; k += 4) {
    const Ints4 flags = block(k);
    const Bytes4 flag_bytes = __builtin_convertvector(flags, Bytes4);
    std::memcpy(flags_out + k, &flag_bytes, sizeof flag_bytes);
    valid_lanes -= (flags & kValid) != 0;
    plane_lanes -= (flags & kPlane) != 0;
    // The gap set is a tenth of a frame and comes in patches: most blocks
    // have none of it, and the branch is well predicted.
    const Ints4 gap_bits = (flags & kGap) & ((flags & list_skips) == 0);
    if ((gap_bits[0] | gap_bits[1] | gap_bits[2] | gap_bits[3]) == 0) continue;
    for (int j = 0; j < 4; ++j) {
      gap_out[gap_count] = static_cast<std::int32_t>(k + j);
      gap_count += gap_bits[j] != 0;
    }
  }
  if (k < n) {
    const std::size_t rest = n - k;
    const Ints4 flags = tail(k, rest);
    valid_lanes -= (flags & kValid) != 0;
    plane_lanes -= (flags & kPlane) != 0;
    for (std::size_t j = 0; j < rest; ++j) {
      flags_out[k + j] = static_cast<std::uint8_t>(flags[j]);
      gap_out[gap_count] = static_cast<std::int32_t>(k + j);
      gap_count += (flags[j] & kGap) != 0 && (flags[j] & list_skips) == 0;
    }
  }
  for (int j = 0; j < 4; ++j) {
    valid_count += static_cast<std::size_t>(valid_lanes[j]);
    plane_inliers += static_cast<std::size_t>(plane_lanes[j]);
  }
  ws.gap.set_size(gap_count);
  *valid_pixels = static_cast<std::uint32_t>(valid_count);
  return static_cast<std::uint32_t>(plane_inliers);
}

}  // namespace

std::uint32_t gap_distance_test(const OrganizedCloud& cloud, const DetectorConfig& cfg,
                                const Plane& wall, Workspace& ws, std::uint32_t* valid_pixels) {
  const GapTestLimits g{wall.normal.x(),
                        wall.normal.y(),
                        wall.normal.z(),
                        wall.d,
                        cfg.min_range_m,
                        cfg.max_range_m,
                        gap_min_m(cfg),
                        gap_max_m(cfg),
                        cfg.plane_inlier_m,
                        cfg.wall_tolerance_m,
                        0,
                        {}};
  // An invalid pixel's distance is -infinity, so that "raised off the wall"
  // is one comparison that an invalid pixel always fails.
  const CloudPoint* points = cloud.points;
  float* distance_out = ws.signed_distance_m.get();
  float* widen_out = ws.gap_widen_m.get();
  float* inverse_depth_out = ws.inverse_depth_per_m.get();
  const auto block = [&](std::size_t k) {
    return classify_four_pixels(points + k, g, distance_out + k, widen_out + k,
                                inverse_depth_out + k);
  };
  const auto tail = [&](std::size_t k, std::size_t rest) {
    // Padded with invalid points (confidence 0), which count nowhere.
    CloudPoint padded[4] = {};
    float distance[4], widen[4], inverse_depth[4];
    std::memcpy(padded, points + k, rest * sizeof(CloudPoint));
    const Ints4 flags = classify_four_pixels(padded, g, distance, widen, inverse_depth);
    for (std::size_t j = 0; j < rest; ++j) {
      distance_out[k + j] = distance[j];
      widen_out[k + j] = widen[j];
      inverse_depth_out[k + j] = inverse_depth[j];
    }
    return flags;
  };
  return run_gap_pass(cloud.size(), ws, valid_pixels, block, tail, false);
}

void keep_plane_pass(const OrganizedCloud& cloud, Workspace& ws) {
  std::memcpy(ws.plane_distance_m.get(), ws.signed_distance_m.get(), cloud.size() * sizeof(float));
}

bool faces_beside_mount(const DetectorConfig& cfg, float offset_m, const float* faces_m,
                        std::uint32_t face_count) {
  for (std::uint32_t k = 0; k < face_count; ++k) {
    if (face_is_wall(cfg, faces_m[k], offset_m)) return true;
  }
  return false;
}

std::uint32_t gap_distance_shifted(const OrganizedCloud& cloud, const DetectorConfig& cfg,
                                   float offset_m, Workspace& ws, std::uint32_t* valid_pixels,
                                   const float* faces_m, std::uint32_t face_count) {
  GapTestLimits g{};
  g.gap_lo_m = gap_min_m(cfg);
  g.gap_hi_m = gap_max_m(cfg);
  g.plane_inlier_m = cfg.plane_inlier_m;
  g.wall_tolerance_m = cfg.wall_tolerance_m;
  for (std::uint32_t k = 0; k < face_count && g.face_count < kMaxWallFaces; ++k) {
    if (face_is_wall(cfg, faces_m[k], offset_m)) g.face_m[g.face_count++] = faces_m[k];
  }
  const float* plane_distance = ws.plane_distance_m.get();
  const float* widen = ws.gap_widen_m.get();
  float* distance_out = ws.signed_distance_m.get();
  const auto block = [&](std::size_t k) {
    return classify_four_shifted(plane_distance + k, widen + k, g, offset_m, distance_out + k);
  };
  const auto tail = [&](std::size_t k, std::size_t rest) {
    // Padded with invalid pixels (-infinity).
    const float inf = std::numeric_limits<float>::infinity();
    float padded_distance[4] = {-inf, -inf, -inf, -inf}, padded_widen[4] = {}, distance[4];
    std::memcpy(padded_distance, plane_distance + k, rest * sizeof(float));
    std::memcpy(padded_widen, widen + k, rest * sizeof(float));
    const Ints4 flags = classify_four_shifted(padded_distance, padded_widen, g, offset_m, distance);
    for (std::size_t j = 0; j < rest; ++j) distance_out[k + j] = distance[j];
    return flags;
  };
  return run_gap_pass(cloud.size(), ws, valid_pixels, block, tail,
                      plane_left_out_of_gap_list(cfg, offset_m));
}

bool plane_left_out_of_gap_list(const DetectorConfig& cfg, float offset_m) {
  // The plane's own search keeps the list the full pass makes, whichever
  // pass wrote it.
  if (offset_m == 0.0f) return false;
  const float front_above_plane_m =
      cfg.handrail.bar_center_offset_m + 0.5f * cfg.handrail.bar_depth_m + offset_m;
  return front_above_plane_m > cfg.plane_inlier_m + kPlaneBandClearanceM;
}

}  // namespace estimator
