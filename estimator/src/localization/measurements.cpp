#include "estimator/localization/measurements.hpp"

namespace estimator::localization {

int add_features(const Eigen::Vector3d* p_cam_m, int n, FeatureKind kind, HandrailMeasurement* m) {
  const Eigen::Isometry3d T_handrail_cam = m->T_cam_handrail.inverse(Eigen::Isometry);
  int added = 0;
  for (int k = 0; k < n && m->num_features < kMaxInputFeatures; ++k, ++added) {
    HandrailFeature& f = m->features[static_cast<std::size_t>(m->num_features++)];
    f.p_cam_m = p_cam_m[k];
    f.p_handrail_m = T_handrail_cam * p_cam_m[k];
    f.kind = kind;
  }
  return added;
}

}  // namespace estimator::localization
