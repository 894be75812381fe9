#include "plane_sharpness.hpp"

#include <cmath>
#include <cstring>

#include "four_lanes.hpp"

namespace estimator {
namespace {

// How sharply the points pile up along a normal: the sum of squares of a
// histogram of their distances along it (4 mm bins). Parallel faces at any
// depths each fall into a bin or two along their own normal and smear over
// many along a tilted one.
constexpr float kSharpBinM = 0.004f;
constexpr int kSharpBins = 256;

// A RANSAC plane may also pivot across two faces a few centimetres apart
// so that both fall into its inlier band, one of them into a bin or two
// along its normal: then it is itself a local maximum of the sharpness, and
// sharpest_normal, started there, finds no slope toward the faces' own
// normal 8 to 10 deg away (seen at 0.2 to 0.3 m from an overhead rail, the
// rail's track a strip 2.8 cm proud of the wall). The sharpness falls off
// within 3 to 4 deg of a face's normal, so a grid of tilts 2 deg apart to
// 10 deg each way has a point on that slope. It is scored on the plane's
// own inliers only (a copy on the stack): the faces it straddles, not
// another wall of the view that happens to be sharper (on every point it
// took other walls of the Columbus module views, 15 to 35 deg away). Its
// sharpest point seeds the search when it beats the plane's own normal
// there.
constexpr int kGridSteps = 5;               // each way: 2, 4, ... 10 deg
constexpr float kGridStepRad = 0.0349066f;  // 2 deg
// The inliers lie in the plane's band, and a tilt of 10 deg moves them by a
// few centimetres more: 64 bins of the search's 4 mm, centred on the plane,
// hold them (a quarter of the search's histogram to clear and sum, and at
// most 128 points, per evaluation).
constexpr int kGridBins = 64;
constexpr std::size_t kMaxGridPoints = 128;

// Sum of squares of the inliers' 4 mm histogram along `n`, about the point
// `on_plane` (the same measure as normal_sharpness).
std::uint64_t band_sharpness(const Eigen::Vector3f& n, const Eigen::Vector3f& on_plane,
                             const float* x, const float* y, const float* z, std::size_t m) {
  std::uint32_t count[kGridBins] = {};
  constexpr float kInverseBin = 1.0f / kSharpBinM;
  const float base = n.dot(on_plane) - 0.5f * kGridBins * kSharpBinM;
  for (std::size_t k = 0; k < m; ++k) {
    const float bin = (n.x() * x[k] + n.y() * y[k] + n.z() * z[k] - base) * kInverseBin;
    if (bin >= 0.0f && bin < static_cast<float>(kGridBins)) ++count[static_cast<int>(bin)];
  }
  std::uint64_t sum = 0;
  for (const std::uint32_t c : count) sum += static_cast<std::uint64_t>(c) * c;
  return sum;
}

}  // namespace

std::uint64_t normal_sharpness(const Eigen::Vector3f& n, const float* x, const float* y,
                               const float* z, std::size_t m) {
  using four_lanes::Floats4;
  using four_lanes::Ints4;
  // Four histograms, one per lane, added at the end: the points of a face
  // fall into the same few bins, and one histogram's increments would wait
  // on each other. Four points at a time, with the scalar expression's
  // operations in its order (the same bins).
  std::uint32_t count[4][kSharpBins] = {};
  const float nx = n.x(), ny = n.y(), nz = n.z();
  const float base = nx * x[0] + ny * y[0] + nz * z[0] - 0.5f * kSharpBins * kSharpBinM;
  std::size_t k = 0;
  for (; k + 4 <= m; k += 4) {
    Floats4 xs, ys, zs;
    std::memcpy(&xs, x + k, sizeof xs);
    std::memcpy(&ys, y + k, sizeof ys);
    std::memcpy(&zs, z + k, sizeof zs);
    const Floats4 bin = (nx * xs + ny * ys + nz * zs - base) / kSharpBinM;
    // Lanes outside the histogram (or NaN) add 0 to bin 0, and only
    // values in range are converted.
    const Ints4 inside = (bin >= 0.0f) & (bin < static_cast<float>(kSharpBins));
    const Floats4 zero = {0.0f, 0.0f, 0.0f, 0.0f};
    const Ints4 index = __builtin_convertvector(inside ? bin : zero, Ints4);
    for (int j = 0; j < 4; ++j) count[j][index[j]] += static_cast<std::uint32_t>(inside[j]) & 1u;
  }
  for (; k < m; ++k) {
    const float bin = (nx * x[k] + ny * y[k] + nz * z[k] - base) / kSharpBinM;
    if (bin >= 0.0f && bin < static_cast<float>(kSharpBins)) ++count[0][static_cast<int>(bin)];
  }
  std::uint64_t sum = 0;
  for (int b = 0; b < kSharpBins; ++b) {
    const std::uint64_t c = count[0][b] + count[1][b] + count[2][b] + count[3][b];
    sum += c * c;
  }
  return sum;
}

// A RANSAC plane scored with the inlier band can lie tilted across two or
// three rack faces centimetres apart, a strip of each inside the band, with
// more support than any one face (seen: 7 deg across faces 6 cm apart), and
// refits keep it there. The faces' own normal is where the points pile up
// most sharply: a coordinate search over tilts of the normal, halving the
// step from 8 deg to 0.25 deg (a fixed 6 x 4 evaluations), finds it.

Eigen::Vector3f sharpest_normal(Eigen::Vector3f n, const float* x, const float* y, const float* z,
                                std::size_t m) {
  std::uint64_t best = normal_sharpness(n, x, y, z, m);
  for (float step_rad = 0.14f; step_rad > 0.004f; step_rad *= 0.5f) {
    const Eigen::Vector3f u = n.unitOrthogonal(), v = n.cross(u);
    const Eigen::Vector3f dirs[4] = {u, -u, v, -v};
    const float t = std::tan(step_rad);
    Eigen::Vector3f best_n = n;
    for (const Eigen::Vector3f& dir : dirs) {
      const Eigen::Vector3f candidate = (n + t * dir).normalized();
      const std::uint64_t s = normal_sharpness(candidate, x, y, z, m);
      if (s > best) {
        best = s;
        best_n = candidate;
      }
    }
    n = best_n;
  }
  return n;
}

Eigen::Vector3f sharpest_grid_tilt(const Plane& plane, float band_m, const float* x, const float* y,
                                   const float* z, std::size_t m) {
  const Eigen::Vector3f& n = plane.normal;
  float gx[kMaxGridPoints], gy[kMaxGridPoints], gz[kMaxGridPoints];
  std::size_t inliers = 0;
  for (std::size_t k = 0; k < m; ++k) {
    inliers += std::fabs(n.x() * x[k] + n.y() * y[k] + n.z() * z[k] + plane.d) <= band_m;
  }
  // Every stride-th inlier, spread over the view as the scored points are.
  const std::size_t stride = (inliers + kMaxGridPoints - 1) / kMaxGridPoints;
  std::size_t g = 0, seen = 0;
  for (std::size_t k = 0; k < m && g < kMaxGridPoints; ++k) {
    if (!(std::fabs(n.x() * x[k] + n.y() * y[k] + n.z() * z[k] + plane.d) <= band_m)) continue;
    if (seen++ % stride != 0) continue;
    gx[g] = x[k];
    gy[g] = y[k];
    gz[g] = z[k];
    ++g;
  }
  const Eigen::Vector3f on_plane = -plane.d * n;
  const Eigen::Vector3f u = n.unitOrthogonal(), v = n.cross(u);
  Eigen::Vector3f best_n = n;
  std::uint64_t best = band_sharpness(n, on_plane, gx, gy, gz, g);
  float tilt[2 * kGridSteps + 1];
  for (int i = -kGridSteps; i <= kGridSteps; ++i) {
    tilt[i + kGridSteps] = std::tan(static_cast<float>(i) * kGridStepRad);
  }
  for (int i = -kGridSteps; i <= kGridSteps; ++i) {
    for (int j = -kGridSteps; j <= kGridSteps; ++j) {
      if (i == 0 && j == 0) continue;
      const Eigen::Vector3f candidate =
          (n + tilt[i + kGridSteps] * u + tilt[j + kGridSteps] * v).normalized();
      const std::uint64_t s = band_sharpness(candidate, on_plane, gx, gy, gz, g);
      if (s > best) {
        best = s;
        best_n = candidate;
      }
    }
  }
  return best_n;
}
}  // namespace estimator
