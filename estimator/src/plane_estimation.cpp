#include "estimator/plane_estimation.hpp"

#include "estimator/moments.hpp"
#include "four_lanes.hpp"
#include "plane_sharpness.hpp"

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstring>

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

// Moves the plane along its normal onto the mode of the points' distances.
bool shift_to_main_surface(const float* x, const float* y, const float* z, std::size_t m,
                           Plane* plane, std::uint32_t* peak_points = nullptr) {
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
  plane->d -= lo + (static_cast<float>(best) + 0.5f) * kModeBinM;
  if (peak_points != nullptr) *peak_points = best_count;
  return true;
}

// How many points pile onto the most populated surface along `normal`
// (within a mode's three bins, 6 mm), about the plane `through`'s point on
// the view's axis: the faces of a wall along their own normal hold many,
// along a normal a few degrees off their points spread over the bins.
std::uint32_t main_surface_points(const float* x, const float* y, const float* z, std::size_t m,
                                  const Plane& through, const Eigen::Vector3f& normal) {
  Plane along = through;
  along.normal = normal;
  along.d = -normal.dot(-through.d * through.normal);
  std::uint32_t points = 0;
  return shift_to_main_surface(x, y, z, m, &along, &points) ? points : 0;
}

bool refit_on_main_surface(const float* x, const float* y, const float* z, std::size_t m,
                           Plane* plane) {
  Plane shifted = *plane;
  if (!shift_to_main_surface(x, y, z, m, &shifted)) return false;
  std::uint32_t support = 0;
  for (int pass = 0; pass < 2; ++pass) {
    if (!refit_plane(x, y, z, m, kTightHalfWidthM, &shifted, &support) || support < 3) return false;
  }
  *plane = shifted;
  return true;
}

// Within a degree of the search's normal the broad fit stands.
constexpr float kSharperCos = 0.99985f;  // cos 1 deg
// A least-squares refit of one face may move the normal by the noise, not
// by degrees: further than this it has taken a neighbouring face too.
constexpr float kRefitKeepsNormalCos = 0.9998f;  // cos 1.15 deg
constexpr float kKeepBroadCos = 0.999986f;       // cos 0.3 deg

// The faces' shared normal refined by least squares over the faces
// themselves: along the current normal each face is a peak of the points'
// distances (1 mm bins within 3.2 cm of the plane, at most kMaxFaces
// peaks); the points within kFaceHalfWidthM of a peak, less their own
// face's centroid, pile into one scatter whose direction of least spread is
// the normal all the faces share. The steps between faces go with the
// centroids. Twice, the second time along the first result.
constexpr float kFaceBinM = 0.001f;
constexpr int kFaceBins = 64;  // +-3.2 cm
constexpr int kMaxFaces = 4;
constexpr float kFaceHalfWidthM = 0.004f;
constexpr float kFaceMinShare = 0.05f;  // of the points within the search, for a peak

bool pooled_faces_normal(const float* x, const float* y, const float* z, std::size_t m,
                         const Plane& through, Eigen::Vector3f* normal, float* faces_span_m) {
  Eigen::Vector3f n = *normal;
  *faces_span_m = 0.0f;
  const Eigen::Vector3f on_plane = -through.d * through.normal;
  for (int pass = 0; pass < 2; ++pass) {
    const float d = -n.dot(on_plane);
    const float lo = -0.5f * kFaceBins * kFaceBinM;
    std::uint32_t count[kFaceBins] = {};
    std::uint32_t total = 0;
    for (std::size_t k = 0; k < m; ++k) {
      const float bin = (n.x() * x[k] + n.y() * y[k] + n.z() * z[k] + d - lo) / kFaceBinM;
      if (bin >= 0.0f && bin < static_cast<float>(kFaceBins)) {
        ++count[static_cast<int>(bin)];
        ++total;
      }
    }
    // Peaks of the histogram smoothed over 5 bins, strongest first, each at
    // least two face half-widths from the ones before.
    float smooth[kFaceBins] = {};
    for (int b = 2; b + 2 < kFaceBins; ++b) {
      smooth[b] = static_cast<float>(count[b - 2] + 2 * count[b - 1] + 3 * count[b] +
                                     2 * count[b + 1] + count[b + 2]) /
                  9.0f;
    }
    float face_m[kMaxFaces];
    int faces = 0;
    for (int f = 0; f < kMaxFaces; ++f) {
      int best = -1;
      for (int b = 2; b + 2 < kFaceBins; ++b) {
        const float centre = lo + (static_cast<float>(b) + 0.5f) * kFaceBinM;
        bool taken = false;
        for (int g = 0; g < faces; ++g)
          taken |= std::fabs(centre - face_m[g]) < 2.0f * kFaceHalfWidthM;
        if (!taken && (best < 0 || smooth[b] > smooth[best])) best = b;
      }
      if (best < 0 || smooth[best] * 5.0f < kFaceMinShare * static_cast<float>(total)) break;
      face_m[faces++] = lo + (static_cast<float>(best) + 0.5f) * kFaceBinM;
    }
    if (faces == 0) return false;
    *faces_span_m = 0.0f;
    for (int f = 1; f < faces; ++f) {
      *faces_span_m = std::fmax(*faces_span_m, std::fabs(face_m[f] - face_m[0]));
    }
    PointMoments moments[kMaxFaces];
    for (int f = 0; f < faces; ++f) moments[f].set_reference(x[0], y[0], z[0]);
    for (std::size_t k = 0; k < m; ++k) {
      const float s = n.x() * x[k] + n.y() * y[k] + n.z() * z[k] + d;
      int nearest = -1;
      float nearest_m = kFaceHalfWidthM;
      for (int f = 0; f < faces; ++f) {
        const float e = std::fabs(s - face_m[f]);
        if (e < nearest_m) {
          nearest_m = e;
          nearest = f;
        }
      }
      if (nearest >= 0) moments[nearest].add(x[k], y[k], z[k]);
    }
    Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
    double points = 0.0;
    for (int f = 0; f < faces; ++f) {
      if (moments[f].n < 3.0) continue;
      scatter += moments[f].covariance() * moments[f].n;
      points += moments[f].n;
    }
    if (points < 50.0) return false;
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver;
    solver.computeDirect(scatter);
    Eigen::Vector3f refined = solver.eigenvectors().col(0).cast<float>();
    if (!refined.allFinite()) return false;
    if (refined.dot(n) < 0.0f) refined = -refined;
    n = refined.normalized();
  }
  *normal = n;
  return true;
}

// The mean distance of the points within kTightHalfWidthM of the most
// populated surface along the plane's normal, taken into its offset; the
// normal stays.
bool place_on_main_surface(const float* x, const float* y, const float* z, std::size_t m,
                           Plane* plane) {
  Plane shifted = *plane;
  if (!shift_to_main_surface(x, y, z, m, &shifted)) return false;
  const float a = shifted.normal.x(), b = shifted.normal.y(), c = shifted.normal.z();
  double sum = 0.0;
  std::uint32_t n = 0;
  for (std::size_t k = 0; k < m; ++k) {
    const float s = a * x[k] + b * y[k] + c * z[k] + shifted.d;
    if (std::fabs(s) < kTightHalfWidthM) {
      sum += s;
      ++n;
    }
  }
  if (n < 3) return false;
  shifted.d -= static_cast<float>(sum / n);
  *plane = shifted;
  return true;
}

// Cells: the view cut into square cells, each fit with its own plane over
// its points near the broad plane (within twice its inlier band). A cell on
// one face has the faces' normal up to its noise; a cell astride a step
// between faces tilts its plane to take the step in (and its residual
// stays low, so the residual cannot tell). The cells' normals vote: the
// one with the most points in cells agreeing with it within kCellAgree,
// and the cells that agree with it, pooled (their scatters about their own
// centroids summed), give the normal whose direction of least spread it is.
// The same vote among the cells left over gives a second cluster's normal,
// if three cells agree there: normals[0] is the mode's, normals[1] the
// runner-up's; returns how many.
constexpr int kCellPx = 28;
// Every fourth pixel each way (49 per cell): with the step on by default
// every other pixel cost 50 us a frame more, and the pooled
// cells' normal, the faces' refit after it, gives the same answers on the
// development set (frames in reach 4,428 -> 4,431 of 4,496).
constexpr int kCellStridePx = 4;
constexpr int kMaxCells = 64;
constexpr float kCellGateCos = 0.866f;  // 30 deg: a box's side is no face of the wall
constexpr double kMinCellPoints = 30.0;
constexpr float kCellAgree = 0.035f;  // 2 deg

int pooled_cells_normals(const OrganizedCloud& cloud, const DetectorConfig& cfg, const Plane& broad,
                         Eigen::Vector3f normals[2]) {
  const int cols = static_cast<int>(cloud.width) / kCellPx;
  const int rows = static_cast<int>(cloud.height) / kCellPx;
  if (cols * rows <= 0 || cols * rows > kMaxCells) return 0;
  Eigen::Matrix3d cov[kMaxCells];
  Eigen::Vector3f cell_normals[kMaxCells];
  double count[kMaxCells] = {};
  int cells = 0;
  for (int cr = 0; cr < rows; ++cr) {
    for (int cc = 0; cc < cols; ++cc) {
      PointMoments m;
      bool referenced = false;
      for (int r = cr * kCellPx; r < (cr + 1) * kCellPx; r += kCellStridePx) {
        for (int c = cc * kCellPx; c < (cc + 1) * kCellPx; c += kCellStridePx) {
          const CloudPoint& p = cloud.at(r, c);
          if (!is_usable_point(p, cfg.min_range_m, cfg.max_range_m)) continue;
          if (std::fabs(broad.signed_distance({p.x_m, p.y_m, p.z_m})) >= 2.0f * cfg.plane_inlier_m)
            continue;
          if (!referenced) {
            m.set_reference(p.x_m, p.y_m, p.z_m);
            referenced = true;
          }
          m.add(p.x_m, p.y_m, p.z_m);
        }
      }
      if (m.n < kMinCellPoints) continue;
      const Eigen::Matrix3d c = m.covariance();
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver;
      solver.computeDirect(c);
      const Eigen::Vector3d cell_normal = solver.eigenvectors().col(0);
      if (!cell_normal.allFinite() ||
          std::fabs(cell_normal.cast<float>().dot(broad.normal)) < kCellGateCos) {
        continue;
      }
      cov[cells] = c;
      cell_normals[cells] = cell_normal.cast<float>();
      count[cells] = m.n;
      ++cells;
    }
  }
  if (cells < 3) return 0;
  // The cells' normals in the broad plane's tangent coordinates.
  const Eigen::Vector3f e1 = broad.normal.unitOrthogonal(), e2 = broad.normal.cross(e1);
  float tu[kMaxCells], tv[kMaxCells];
  for (int k = 0; k < cells; ++k) {
    Eigen::Vector3f nk = cell_normals[k];
    if (nk.dot(broad.normal) < 0.0f) nk = -nk;
    tu[k] = nk.dot(e1);
    tv[k] = nk.dot(e2);
  }
  // The cell whose normal has the most cells' normals within kCellAgree
  // of it (the faces' normal, if any cells lie on faces alone), and the
  // cells within that of it.
  // Squared distances: the vote is over every pair of cells.
  constexpr float kCellAgree2 = kCellAgree * kCellAgree;
  const auto agree = [&](int a, int b) {
    const float du = tu[a] - tu[b], dv = tv[a] - tv[b];
    return du * du + dv * dv < kCellAgree2;
  };
  // The mode, then the mode of the cells that disagree with it: another
  // surface in the view (a panel at an angle to the wall) may fill more
  // cells than the wall's faces, whose cells the steps between faces split
  // into several small clusters.
  int modes[2] = {-1, -1};
  for (int pick = 0; pick < 2; ++pick) {
    int mode_votes = 0;
    for (int k = 0; k < cells; ++k) {
      if (pick == 1 && agree(k, modes[0])) continue;
      int votes = 0;
      for (int j = 0; j < cells; ++j) {
        if (pick == 1 && agree(j, modes[0])) continue;
        votes += agree(k, j) ? static_cast<int>(count[j]) : 0;
      }
      if (votes > mode_votes) {
        mode_votes = votes;
        modes[pick] = k;
      }
    }
    if (modes[pick] < 0) break;
  }
  int found = 0;
  for (int pick = 0; pick < 2 && modes[pick] >= 0; ++pick) {
    Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
    int used = 0;
    for (int k = 0; k < cells; ++k) {
      if (!agree(k, modes[pick]) || (pick == 1 && agree(k, modes[0]))) continue;
      scatter += cov[k] * count[k];
      ++used;
    }
    if (used < 3) break;
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver;
    solver.computeDirect(scatter);
    Eigen::Vector3f n = solver.eigenvectors().col(0).cast<float>();
    if (!n.allFinite()) break;
    if (n.dot(broad.normal) < 0.0f) n = -n;
    normals[found++] = n.normalized();
  }
  return found;
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
  const Eigen::Vector3f sharp = sharpest_normal(
      sharpest_grid_tilt(best, cfg.plane_inlier_m, sx, sy, sz, m_score), sx, sy, sz, m_score);
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
  // Optionally, last, the normal the faces share (from the cells of the
  // view that lie on one face, then by least squares over each face about
  // its own centroid), and the most populated face along it: refit there
  // unless that tilts it again (faces too close for the tight band to hold
  // one alone), else only moved onto it.
  Eigen::Vector3f faces_normal;
  float faces_span_m = 0.0f;
  Eigen::Vector3f cell_normals[2];
  const int cell_clusters =
      cfg.plane_faces_normal ? pooled_cells_normals(cloud, cfg, best, cell_normals) : 0;
  if (cell_clusters > 0) {
    // The runner-up is the wall's when it piles more than twice as many
    // of the view's points onto one surface as the mode (on
    // the first development set's dev-rack-table2-iss-mesh-30, frame 231,
    // the mode lay 12.6 deg off the wall, holding 31 points on its main
    // surface against the wall's 130, and every line was searched along
    // it). Twice, not any excess: between clusters of the wall's own cells
    // (a step's cells and a face's, 3 to 6 deg apart) the counts differ by
    // up to a fifth either way, and taking any excess made false frames on
    // dev-rack-no-handrail-wall.
    faces_normal = cell_normals[0];
    if (cell_clusters > 1 &&
        main_surface_points(rx, ry, rz, m_refit, best, cell_normals[1]) >
            2u * main_surface_points(rx, ry, rz, m_refit, best, cell_normals[0])) {
      faces_normal = cell_normals[1];
    }
    pooled_faces_normal(rx, ry, rz, m_refit, best, &faces_normal, &faces_span_m);
  }
  // Only where faces a rack's step apart show (neighbouring rack faces
  // differ by 1 to 5 cm): a flat wall's one face, its histogram split by
  // clutter or a slight tilt into peaks under a centimetre apart, has no
  // steps to tilt the broad fit, and that fit of every point stands there.
  if (faces_span_m >= kRackFaceStepM) {
    // Within a third of a degree the broad fit stands: on a flat wall it
    // is the least-squares fit of every point, finer than any face's.
    if (faces_normal.dot(best.normal) > kKeepBroadCos) faces_normal = best.normal;
    Plane along_faces = best;
    const Eigen::Vector3f on_plane = -best.d * best.normal;
    along_faces.normal = faces_normal;
    along_faces.d = -faces_normal.dot(on_plane);
    Plane refit = along_faces;
    if (refit_on_main_surface(rx, ry, rz, m_refit, &refit) && refit.d > 0.0f &&
        refit.normal.dot(faces_normal) > kRefitKeepsNormalCos) {
      best = refit;
    } else if (place_on_main_surface(rx, ry, rz, m_refit, &along_faces) && along_faces.d > 0.0f) {
      best = along_faces;
    }
  }
  if (best.d < 0.0f) return result;
  const float fraction = static_cast<float>(support) / static_cast<float>(m_refit);
  if (fraction < cfg.plane_min_inlier_fraction) return result;
  result.found = true;
  result.plane = best;
  result.inliers = static_cast<std::uint32_t>(fraction * static_cast<float>(cloud.size()));
  result.faces_span_m = faces_span_m;
  return result;
}

}  // namespace estimator
