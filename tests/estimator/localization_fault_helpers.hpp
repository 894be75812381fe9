// The fault tests' shared pieces (test_localization_faults.cpp,
// test_localization_gp_faults.cpp): a bit-for-bit snapshot of the filter,
// the error relative to the handrail, and a filter converged on the
// simulated world (test_localization_sim.hpp).
#pragma once

#include <memory>

#include "estimator/localization/localization_filter.hpp"
#include "test_localization_sim.hpp"

namespace faulttest {

using estimator::localization::Covariance;
using estimator::localization::Health;
using estimator::localization::LocalizationFilter;
using estimator::localization::NominalState;
using estimator::localization::UpdateStatus;
using locsim::Event;
using locsim::Sim;
using locsim::SimConfig;

struct Snapshot {
  NominalState x;
  Covariance P;
  std::int64_t t_us;
  bool map_valid;
};

inline Snapshot snap(const LocalizationFilter& f) {
  return {f.state(), f.covariance(), f.time_us(), f.handrail_map().valid};
}

inline bool same(const Snapshot& a, const Snapshot& b) {
  return a.x.p_world_body_m == b.x.p_world_body_m && a.x.v_world_body_mps == b.x.v_world_body_mps &&
         a.x.q_world_body.coeffs() == b.x.q_world_body.coeffs() &&
         a.x.gyro_bias_radps == b.x.gyro_bias_radps && a.x.accel_bias_mps2 == b.x.accel_bias_mps2 &&
         a.x.p_world_handrail_m == b.x.p_world_handrail_m &&
         a.x.q_world_handrail.coeffs() == b.x.q_world_handrail.coeffs() && a.P == b.P &&
         a.t_us == b.t_us && a.map_valid == b.map_valid;
}

inline double rel_error(const LocalizationFilter& f, const Sim& sim, double t) {
  return (locsim::estimated_p_handrail_body(f, sim) - sim.true_p_handrail_body(t)).norm();
}

// A filter that has converged on the handrail (BE) for `seconds`.
struct Converged {
  SimConfig sc;
  std::unique_ptr<Sim> sim;
  std::unique_ptr<LocalizationFilter> f;
  int bad_health = 0;
  explicit Converged(double seconds, bool handrail = true, std::uint64_t seed = 21) {
    sc.seed = seed;
    sc.duration_s = 60.0;
    sc.handrail = handrail;
    sim = std::make_unique<Sim>(sc);
    f = std::make_unique<LocalizationFilter>(locsim::sim_filter_config(sc));
    locsim::run(
        *sim, *f, [&](int, double) { bad_health += f->initialized() && f->check() != Health::kOk; },
        [](const Event&, UpdateStatus) {}, locsim::sample_at(*sim, seconds) + 1);
  }
  double now_s() const { return 1e-6 * static_cast<double>(f->time_us()); }
};

}  // namespace faulttest
