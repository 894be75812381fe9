#include "estimator/bar_profile.hpp"

#include <cmath>

#include <Eigen/Geometry>  // cross()

namespace estimator {
namespace {

// Heights above the searched wall, 1 mm bins from 5 cm behind it to 20 cm
// in front: the gap window (3.5 to 8.7 cm for the ISS bar), widened by up
// to twice a pixel's 2 cm noise cap, lies well inside. Beyond-range heights
// count in the end bins.
constexpr int kBins = 250;
constexpr float kBinM = 0.001f;
constexpr float kLowestM = -0.05f;

int bin_of(float height_m) {
  const float x = (height_m - kLowestM) / kBinM;
  if (!(x >= 0.0f)) return 0;  // NaN and -infinity too (none reach here)
  return x < static_cast<float>(kBins - 1) ? static_cast<int>(x) : kBins - 1;
}

}  // namespace

BarProfile measure_bar_profile(const Workspace& ws, const Plane& wall, const CenterLine& line,
                               const IndexList& inliers) {
  BarProfile profile;
  const Eigen::Vector3f across = line.axis.cross(wall.normal);
  const Eigen::Vector3f middle = line.point + 0.5f * (line.t_min_m + line.t_max_m) * line.axis;
  const float across_norm = across.norm();
  if (across_norm > 0.0f && middle.norm() > 0.0f) {
    const Eigen::Vector3f ray = middle.normalized();
    profile.obliquity_rad =
        std::atan2(std::fabs(ray.dot(across)) / across_norm, std::fabs(ray.dot(wall.normal)));
  }
  std::uint32_t histogram[kBins] = {};
  for (std::int32_t i : inliers) ++histogram[bin_of(ws.signed_distance_m[i])];
  profile.count = static_cast<std::uint32_t>(inliers.size());
  if (profile.count == 0) return profile;
  // The bins holding the 10th and the 90th percentile.
  const std::uint64_t n = profile.count;
  std::uint64_t seen = 0;
  int p10 = -1, p90 = -1;
  for (int b = 0; b < kBins && p90 < 0; ++b) {
    seen += histogram[b];
    if (p10 < 0 && 10 * seen >= n) p10 = b;
    if (10 * seen >= 9 * n) p90 = b;
  }
  profile.spread_m = static_cast<float>(p90 - p10) * kBinM;
  return profile;
}

bool profile_fits_bar(const BarProfile& profile, const DetectorConfig& cfg) {
  const HandrailGeometry& h = cfg.handrail;
  if (!(h.bar_depth_m > 1.3f * h.bar_width_m)) return true;
  const float min_obliquity_rad = cfg.profile_min_obliquity_deg * 3.14159265f / 180.0f;
  if (profile.obliquity_rad < min_obliquity_rad || profile.count == 0) return true;
  return profile.spread_m >= cfg.profile_min_spread_m;
}

}  // namespace estimator
