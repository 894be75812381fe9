#include "estimator/plane_estimation.hpp"

#include "estimator/moments.hpp"

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

namespace estimator {
namespace {

bool plane_from_triple(const Eigen::Vector3f& a, const Eigen::Vector3f& b, const Eigen::Vector3f& c,
                       Plane* plane) {
  Eigen::Vector3f n = (b - a).cross(c - a);
  const float norm = n.norm();
  // Near-collinear triples give no plane; 1 cm^2 of spanned area at least.
  if (norm < 1e-4f) return false;
  n /= norm;
  plane->normal = n;
  plane->d = -n.dot(a);
  return true;
}

// The plane through the moments' centroid normal to their direction of
// least spread, oriented so that the camera (the origin) is on its
// positive side.
bool plane_from_moments(const PointMoments& m, Plane* plane) {
  if (m.n < 3.0) return false;
  const Eigen::Matrix3d cov = m.covariance();
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver;
  solver.computeDirect(cov);
  Eigen::Vector3d normal = solver.eigenvectors().col(0);
  if (!normal.allFinite() || normal.norm() < 0.5) return false;
  normal.normalize();
  double d = -normal.dot(m.mean());
  if (d < 0.0) {
    normal = -normal;
    d = -d;
  }
  plane->normal = normal.cast<float>();
  plane->d = static_cast<float>(d);
  return true;
}

// Every step-th point of the refit set into the scoring arrays.
std::size_t gather_score_subsample(const Workspace& ws, std::size_t m_refit, std::size_t capacity) {
  const std::size_t step = (m_refit + capacity - 1) / capacity;
  std::size_t m = 0;
  for (std::size_t k = 0; k < m_refit; k += step, ++m) {
    ws.score_x_m[m] = ws.refit_x_m[k];
    ws.score_y_m[m] = ws.refit_y_m[k];
    ws.score_z_m[m] = ws.refit_z_m[k];
  }
  return m;
}

// RANSAC's score: how many points lie within the inlier distance. Written
// without branches over plain arrays so that the compiler vectorises it.
std::uint32_t count_plane_inliers(const Plane& plane, const float* x, const float* y,
                                  const float* z, std::size_t m, float max_distance_m) {
  const float a = plane.normal.x(), b = plane.normal.y(), c = plane.normal.z(), d = plane.d;
  std::uint32_t score = 0;
  for (std::size_t k = 0; k < m; ++k) {
    score += std::fabs(a * x[k] + b * y[k] + c * z[k] + d) < max_distance_m ? 1u : 0u;
  }
  return score;
}

// The least-squares plane through the points within the distance of
// `plane`; `inliers` is how many there were.
bool refit_plane(const float* x, const float* y, const float* z, std::size_t m,
                 float max_distance_m, Plane* plane, std::uint32_t* inliers) {
  const float a = plane->normal.x(), b = plane->normal.y(), c = plane->normal.z(), d = plane->d;
  PointMoments moments;
  moments.set_reference(x[0], y[0], z[0]);
  for (std::size_t k = 0; k < m; ++k) {
    if (std::fabs(a * x[k] + b * y[k] + c * z[k] + d) < max_distance_m) {
      moments.add(x[k], y[k], z[k]);
    }
  }
  *inliers = static_cast<std::uint32_t>(moments.n);
  return plane_from_moments(moments, plane);
}

// On a rack wall the inliers of the RANSAC plane hold two or three faces a
// centimetre or two apart, and their least-squares plane is tilted between
// them; the mount hypotheses measure heights along its normal across the
// whole view, where a tenth of a degree is millimetres. So the plane is fit
// once more to the most populated surface alone: the mode of the sample's
// distances (2 mm bins), and the points within kTightHalfWidthM of it.
constexpr float kModeBinM = 0.002f;
constexpr int kModeBins = 32;  // +-3.2 cm: the RANSAC inlier band and more
constexpr float kTightHalfWidthM = 0.005f;

bool refit_on_main_surface(const float* x, const float* y, const float* z, std::size_t m,
                           Plane* plane) {
  std::uint32_t count[kModeBins] = {};
  const float a = plane->normal.x(), b = plane->normal.y(), c = plane->normal.z(), d = plane->d;
  const float lo = -0.5f * kModeBins * kModeBinM;
  for (std::size_t k = 0; k < m; ++k) {
    const float bin = (a * x[k] + b * y[k] + c * z[k] + d - lo) / kModeBinM;
    if (bin >= 0.0f && bin < static_cast<float>(kModeBins)) ++count[static_cast<int>(bin)];
  }
  int best = -1;
  std::uint32_t best_count = 0;
  for (int k = 1; k + 1 < kModeBins; ++k) {
    const std::uint32_t n = count[k - 1] + count[k] + count[k + 1];
    if (n > best_count) {
      best_count = n;
      best = k;
    }
  }
  if (best < 0) return false;
  Plane shifted = *plane;
  shifted.d -= lo + (static_cast<float>(best) + 0.5f) * kModeBinM;
  std::uint32_t support = 0;
  for (int pass = 0; pass < 2; ++pass) {
    if (!refit_plane(x, y, z, m, kTightHalfWidthM, &shifted, &support) || support < 3) return false;
  }
  *plane = shifted;
  return true;
}

// How sharply the points pile up along a normal: the sum of squares of a
// histogram of their distances along it (4 mm bins). Parallel faces at any
// depths each fall into a bin or two along their own normal and smear over
// many along a tilted one.
constexpr float kSharpBinM = 0.004f;
constexpr int kSharpBins = 256;

std::uint64_t normal_sharpness(const Eigen::Vector3f& n, const float* x, const float* y,
                               const float* z, std::size_t m) {
  std::uint32_t count[kSharpBins] = {};
  const float base = n.x() * x[0] + n.y() * y[0] + n.z() * z[0] - 0.5f * kSharpBins * kSharpBinM;
  for (std::size_t k = 0; k < m; ++k) {
    const float bin = (n.x() * x[k] + n.y() * y[k] + n.z() * z[k] - base) / kSharpBinM;
    if (bin >= 0.0f && bin < static_cast<float>(kSharpBins)) ++count[static_cast<int>(bin)];
  }
  std::uint64_t sum = 0;
  for (int b = 0; b < kSharpBins; ++b) sum += static_cast<std::uint64_t>(count[b]) * count[b];
  return sum;
}

// A RANSAC plane scored with the inlier band can lie tilted across two or
// three rack faces centimetres apart, a strip of each inside the band, with
// more support than any one face (seen: 7 deg across faces 6 cm apart), and
// refits keep it there. The faces' own normal is where the points pile up
// most sharply: a coordinate search over tilts of the normal, halving the
// step from 8 deg to 0.25 deg (a fixed 6 x 4 evaluations), finds it.
constexpr float kSharperCos = 0.99985f;  // cos 1 deg

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

// How many triples to draw for a 99 % chance that one was all inliers,
// given the best hypothesis's inlier share: log(0.01) / log(1 - w^3),
// within [min_iterations, max_iterations].
std::uint32_t ransac_iterations(float inlier_share, std::uint32_t min_iterations,
                                std::uint32_t max_iterations) {
  constexpr double kLogMissChance = -4.605170185988091;  // log(0.01)
  const double all_in = static_cast<double>(inlier_share) * inlier_share * inlier_share;
  if (!(all_in > 0.0)) return max_iterations;
  if (all_in >= 1.0) return min_iterations;
  const double needed = std::ceil(kLogMissChance / std::log1p(-all_in));
  if (needed >= static_cast<double>(max_iterations)) return max_iterations;
  return std::max(min_iterations, static_cast<std::uint32_t>(needed));
}

}  // namespace

bool fit_plane_least_squares(const OrganizedCloud& cloud, const std::int32_t* indices,
                             std::size_t count, Plane* plane) {
  if (count < 3) return false;
  PointMoments moments;
  const CloudPoint& ref = cloud.points[indices[0]];
  moments.set_reference(ref.x_m, ref.y_m, ref.z_m);
  for (std::size_t k = 0; k < count; ++k) {
    const CloudPoint& p = cloud.points[indices[k]];
    moments.add(p.x_m, p.y_m, p.z_m);
  }
  return plane_from_moments(moments, plane);
}

std::size_t sample_valid_points(const OrganizedCloud& cloud, const DetectorConfig& cfg,
                                Workspace& ws) {
  const std::size_t n = cloud.size();
  // Every step-th pixel in raster order: a lattice over the whole frame.
  const std::size_t step = (n + Workspace::kMaxRefitSamples - 1) / Workspace::kMaxRefitSamples;
  ws.sample.clear();
  std::size_t m = 0;
  for (std::size_t i = 0; i < n; i += step) {
    const CloudPoint& p = cloud.points[i];
    if (!is_usable_point(p, cfg.min_range_m, cfg.max_range_m)) continue;
    ws.sample.push(static_cast<std::int32_t>(i));
    ws.refit_x_m[m] = p.x_m;
    ws.refit_y_m[m] = p.y_m;
    ws.refit_z_m[m] = p.z_m;
    ++m;
  }
  return m;
}

PlaneEstimate estimate_plane(const OrganizedCloud& cloud, const DetectorConfig& cfg, Random& rng,
                             Workspace& ws) {
  PlaneEstimate result;
  const std::size_t m_refit = ws.sample.size();
  if (m_refit < 3) return result;
  // The refits use the whole sample (a few thousand points, far more than
  // the noise needs); hypotheses are scored on a few hundred of them.
  const std::size_t m_score = gather_score_subsample(
      ws, m_refit, std::min<std::size_t>(cfg.plane_score_samples, Workspace::kMaxScoreSamples));
  const float* rx = ws.refit_x_m.get();
  const float* ry = ws.refit_y_m.get();
  const float* rz = ws.refit_z_m.get();
  const std::uint32_t m32 = static_cast<std::uint32_t>(m_refit);

  Plane best;
  std::uint32_t best_score = 0;
  std::uint32_t iterations = cfg.plane_max_iterations;  // until a hypothesis is scored
  for (std::uint32_t it = 0; it < iterations; ++it) {
    const std::uint32_t i = rng.below(m32), j = rng.below(m32), k = rng.below(m32);
    Plane hypothesis;
    if (!plane_from_triple({rx[i], ry[i], rz[i]}, {rx[j], ry[j], rz[j]}, {rx[k], ry[k], rz[k]},
                           &hypothesis)) {
      continue;
    }
    const std::uint32_t score =
        count_plane_inliers(hypothesis, ws.score_x_m.get(), ws.score_y_m.get(), ws.score_z_m.get(),
                            m_score, cfg.plane_inlier_m);
    if (score > best_score) {
      best_score = score;
      best = hypothesis;
      iterations = ransac_iterations(static_cast<float>(score) / static_cast<float>(m_score),
                                     cfg.plane_iterations, cfg.plane_max_iterations);
    }
  }
  if (best_score < cfg.plane_min_inlier_fraction * static_cast<float>(m_score)) return result;

  // Two refits: the second one sees inliers of a plane no longer tilted by
  // the triple's noise. The per-pixel distances are written later, by the
  // gap distance test in its single pass over the frame.
  std::uint32_t support = 0;
  for (int pass = 0; pass < 2; ++pass) {
    if (!refit_plane(rx, ry, rz, m_refit, cfg.plane_inlier_m, &best, &support)) return result;
  }
  // The normal the faces share, through the broad plane's own centre of
  // the view; the refit below moves it onto the most populated face. Kept
  // only if that refit succeeds: with too few points near the mode (a very
  // noisy far wall) the broad fit stands.
  const float* sx = ws.score_x_m.get();
  const float* sy = ws.score_y_m.get();
  const float* sz = ws.score_z_m.get();
  Plane tight = best;
  const Eigen::Vector3f sharp = sharpest_normal(best.normal, sx, sy, sz, m_score);
  // Within a degree the broad fit stands: it is the least-squares fit of
  // one wall, finer than the search's steps.
  const bool tilted = sharp.allFinite() && sharp.dot(best.normal) < kSharperCos;
  if (tilted) {
    // Through the same point of the broad plane on the view's axis.
    const Eigen::Vector3f on_plane = -best.d * best.normal;
    tight.normal = sharp;
    tight.d = -sharp.dot(on_plane);
  }
  if (refit_on_main_surface(rx, ry, rz, m_refit, &tight) && tight.d > 0.0f) {
    // Faces a centimetre apart blur into one under the noise, and the
    // refit across their step tilts again: it keeps its offset, and the
    // search's normal, where that is the sharper.
    if (tilted && normal_sharpness(sharp, sx, sy, sz, m_score) >
                      normal_sharpness(tight.normal, sx, sy, sz, m_score)) {
      const Eigen::Vector3f on_plane = -tight.d * tight.normal;
      tight.normal = sharp;
      tight.d = -sharp.dot(on_plane);
    }
    best = tight;
  }
  if (best.d < 0.0f) return result;
  const float fraction = static_cast<float>(support) / static_cast<float>(m_refit);
  if (fraction < cfg.plane_min_inlier_fraction) return result;
  result.found = true;
  result.plane = best;
  result.inliers = static_cast<std::uint32_t>(fraction * static_cast<float>(cloud.size()));
  return result;
}

}  // namespace estimator
