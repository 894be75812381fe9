// The simulated IMU and general-purpose localizer: their statistics are the
// ones they are configured with (rate, jitter, white noise, bias random
// walk, saturation; GP rate, latency, dropouts, bias size and drift), the
// samples integrate back to the motion that made them, and a seed gives one
// sequence.
#include <cmath>
#include <vector>

#include "cmocka_cpp.hpp"
#include "sim_hal/sim_gp_localizer.hpp"
#include "sim_hal/sim_imu.hpp"

using sim_hal::GpFix;
using sim_hal::GpLocalizerParams;
using sim_hal::ImuParams;
using sim_hal::ImuReading;
using sim_hal::SimGpLocalizer;
using sim_hal::SimImu;

namespace {

constexpr std::int64_t kTickUs = 10000;  // the HIL world's physics rate

struct Stats {
  double n = 0, sum = 0, sum2 = 0;
  void add(double x) {
    n += 1;
    sum += x;
    sum2 += x * x;
  }
  double mean() const { return sum / n; }
  double sd() const { return std::sqrt(std::max(0.0, sum2 / n - mean() * mean())); }
};

// Every sample of `seconds` of a motion given by pose(t_s).
template <typename PoseAt>
std::vector<ImuReading> run_imu(SimImu& imu, double seconds, PoseAt pose) {
  std::vector<ImuReading> all;
  ImuReading out[SimImu::kMaxPerTick];
  for (std::int64_t t = 0; t <= static_cast<std::int64_t>(seconds * 1e6); t += kTickUs) {
    const int n = imu.on_truth(t, pose(1e-6 * static_cast<double>(t)), out);
    for (int k = 0; k < n; ++k) all.push_back(out[k]);
  }
  return all;
}

Eigen::Isometry3d at_rest(double) {
  return Eigen::Isometry3d::Identity();
}

void test_imu_rate_jitter_and_white_noise_at_rest(void**) {
  ImuParams p;
  p.gyro_bias_rw_radps2_rthz = 0.0;
  p.accel_bias_rw_mps3_rthz = 0.0;
  SimImu imu(p, 3);
  const std::vector<ImuReading> s = run_imu(imu, 60.0, at_rest);
  assert_true(std::fabs(static_cast<double>(s.size()) - 60.0 * 62.5) <= 2.0);
  Stats dt, gx, az;
  for (std::size_t k = 1; k < s.size(); ++k) {
    const double d = static_cast<double>(s[k].t_us - s[k - 1].t_us);
    assert_true(std::fabs(d - 16000.0) <= 2.0 * p.jitter_us + 1.0);
    dt.add(d);
    gx.add(s[k].omega_body_radps.x());
    az.add(s[k].a_body_mps2.z());
  }
  assert_near(dt.mean(), 16000.0, 5.0);
  // Uniform jitter on both ends: sd of the interval = sqrt(2/3) * jitter.
  assert_near(dt.sd(), std::sqrt(2.0 / 3.0) * p.jitter_us, 0.1 * p.jitter_us);
  assert_near(gx.mean(), imu.gyro_bias_radps().x(), 3e-5);
  assert_near(az.mean(), imu.accel_bias_mps2().z(), 6e-4);
  assert_near(gx.sd(), p.gyro_noise_radps_rthz * std::sqrt(62.5), 0.05 * 3.95e-4);
  assert_near(az.sd(), p.accel_noise_mps2_rthz * std::sqrt(62.5), 0.05 * 7.9e-3);
  assert_true(std::fabs(imu.gyro_bias_radps().x()) <= p.gyro_bias0_radps);
}

void test_imu_bias_random_walk_spreads_as_sqrt_time(void**) {
  ImuParams p;
  p.accel_bias_rw_mps3_rthz = 1e-3;
  Stats d;
  constexpr double kSeconds = 40.0;
  for (std::uint64_t seed = 1; seed <= 120; ++seed) {
    SimImu imu(p, seed);
    const Eigen::Vector3d b0 = imu.accel_bias_mps2();
    run_imu(imu, kSeconds, at_rest);
    const Eigen::Vector3d moved = imu.accel_bias_mps2() - b0;
    for (int k = 0; k < 3; ++k) d.add(moved[k]);
  }
  // 360 draws of N(0, rw^2 T): the sample sd within 15 % of rw sqrt(T).
  const double expected = p.accel_bias_rw_mps3_rthz * std::sqrt(kSeconds);
  assert_near(d.sd(), expected, 0.15 * expected);
  assert_near(d.mean(), 0.0, 0.25 * expected);
}

// Constant angular rate about a tilted axis and constant world acceleration:
// the noise-free samples integrate (as the filter does) back to the motion.
void test_imu_samples_integrate_back_to_the_motion(void**) {
  ImuParams p;
  p.gyro_noise_radps_rthz = p.accel_noise_mps2_rthz = 0.0;
  p.gyro_bias_rw_radps2_rthz = p.accel_bias_rw_mps3_rthz = 0.0;
  p.gyro_bias0_radps = p.accel_bias0_mps2 = 0.0;
  const Eigen::Vector3d w_world(0.05, -0.02, 0.2), a_world(0.03, -0.02, 0.01);
  const auto pose = [&](double t) {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = Eigen::AngleAxisd(w_world.norm() * t, w_world.normalized()).toRotationMatrix();
    T.translation() = Eigen::Vector3d(1.0, 0.5, 0.0) + 0.5 * a_world * t * t;
    return T;
  };
  SimImu imu(p, 5);
  const std::vector<ImuReading> s = run_imu(imu, 8.0, pose);
  // Strapdown from the first sample's true state.
  Eigen::Quaterniond q(pose(1e-6 * static_cast<double>(s[0].t_us)).linear());
  Eigen::Vector3d v = a_world * 1e-6 * static_cast<double>(s[0].t_us);
  Eigen::Vector3d x = pose(1e-6 * static_cast<double>(s[0].t_us)).translation();
  for (std::size_t k = 1; k < s.size(); ++k) {
    const double dt = 1e-6 * static_cast<double>(s[k].t_us - s[k - 1].t_us);
    const Eigen::Vector3d phi = s[k].omega_body_radps * dt;
    const Eigen::Quaterniond dq(Eigen::AngleAxisd(phi.norm(), phi.normalized()));
    const Eigen::Quaterniond q_next = (q * dq).normalized();
    const Eigen::Vector3d a = q.slerp(0.5, q_next) * s[k].a_body_mps2;
    x += v * dt + 0.5 * a * dt * dt;
    v += a * dt;
    q = q_next;
    // The rate seen in the body frame is the world rate turned into it.
    assert_true((s[k].omega_body_radps - q.conjugate() * w_world).norm() < 1e-6);
  }
  const Eigen::Isometry3d T_end = pose(1e-6 * static_cast<double>(s.back().t_us));
  // Piecewise-constant velocity between 10 ms ticks: the flyer's own model.
  assert_true((x - T_end.translation()).norm() < 2e-3);
  assert_true(Eigen::AngleAxisd(q.conjugate() * Eigen::Quaterniond(T_end.linear())).angle() < 1e-6);
}

void test_imu_saturates_and_flags(void**) {
  ImuParams p;
  p.max_rate_radps = 1.0;
  SimImu imu(p, 7);
  const auto spin = [](double t) {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = Eigen::AngleAxisd(2.0 * t, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    return T;
  };
  const std::vector<ImuReading> s = run_imu(imu, 1.0, spin);
  assert_true(s.size() > 50);
  for (std::size_t k = 1; k < s.size(); ++k) {
    assert_true(s[k].saturated);
    assert_near(s[k].omega_body_radps.z(), 1.0, 1e-12);
  }
}

void test_imu_same_seed_same_samples(void**) {
  ImuParams p;
  SimImu a(p, 11), b(p, 11), c(p, 12);
  const std::vector<ImuReading> sa = run_imu(a, 2.0, at_rest), sb = run_imu(b, 2.0, at_rest),
                                sc = run_imu(c, 2.0, at_rest);
  assert_int_equal(sa.size(), sb.size());
  bool differ = false;
  for (std::size_t k = 0; k < sa.size(); ++k) {
    assert_true(sa[k].t_us == sb[k].t_us);
    assert_true(sa[k].omega_body_radps == sb[k].omega_body_radps);
    assert_true(sa[k].a_body_mps2 == sb[k].a_body_mps2);
    if (k < sc.size() && sa[k].omega_body_radps != sc[k].omega_body_radps) differ = true;
  }
  assert_true(differ);
}

// A stalled tick loses the samples beyond kMaxPerTick, counted.
void test_imu_stalled_tick_drops_and_counts(void**) {
  SimImu imu(ImuParams{}, 2);
  ImuReading out[SimImu::kMaxPerTick];
  imu.on_truth(0, Eigen::Isometry3d::Identity(), out);
  const int n = imu.on_truth(500000, Eigen::Isometry3d::Identity(), out);  // 0.5 s: 31 due
  assert_int_equal(n, SimImu::kMaxPerTick);
  assert_true(imu.dropped() >= 14);
}

std::vector<GpFix> run_gp(SimGpLocalizer& gp, double seconds,
                          const Eigen::Isometry3d& T = Eigen::Isometry3d::Identity(),
                          double from_s = 0.0) {
  std::vector<GpFix> all;
  GpFix f;
  for (std::int64_t t = static_cast<std::int64_t>(from_s * 1e6);
       t <= static_cast<std::int64_t>((from_s + seconds) * 1e6); t += kTickUs) {
    gp.on_truth(t, T);
    while (gp.poll(t, &f)) {
      assert_true(f.delivery_time_us <= t);
      all.push_back(f);
    }
  }
  return all;
}

void test_gp_rate_latency_and_dropouts(void**) {
  GpLocalizerParams p;
  SimGpLocalizer gp(p, 4);
  const std::vector<GpFix> f = run_gp(gp, 1200.0);
  assert_near(static_cast<double>(gp.captured()) / 1200.0, p.rate_hz, 0.05);
  assert_near(static_cast<double>(gp.dropped()) / static_cast<double>(gp.captured()),
              p.dropout_probability, 0.015);
  assert_int_equal(f.size(), gp.captured() - gp.dropped());
  Stats latency;
  for (std::size_t k = 0; k < f.size(); ++k) {
    const double l = 1e-6 * static_cast<double>(f[k].delivery_time_us - f[k].capture_time_us);
    assert_true(l >= p.latency_min_s - 1e-6);
    assert_true(l <= p.latency_max_s + 0.01);  // the 10 ms tick
    latency.add(l);
    if (k > 0) assert_true(f[k].capture_time_us > f[k - 1].capture_time_us);
  }
  assert_near(latency.mean(), 0.5 * (p.latency_min_s + p.latency_max_s), 0.01);
}

// "5 cm and 2 deg off": every fix that far off plus white noise, the
// direction of the error wandering; the covariance is the claimed one.
void test_gp_bias_size_drift_and_white_noise(void**) {
  GpLocalizerParams p;
  p.bias_m = 0.05;
  p.bias_rad = 2.0 * M_PI / 180.0;
  p.dropout_probability = 0.0;
  SimGpLocalizer gp(p, 9);
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation() << 2.0, -1.0, 0.5;
  const std::vector<GpFix> f = run_gp(gp, 600.0, T);
  Stats size_m, angle, step;
  for (std::size_t k = 0; k < f.size(); ++k) {
    size_m.add((f[k].T_world_body.translation() - T.translation()).norm());
    angle.add(Eigen::AngleAxisd(f[k].T_world_body.linear()).angle());
    if (k > 0) step.add(f[k].error_p_m.x() - f[k - 1].error_p_m.x());
    assert_near(f[k].cov(0, 0), p.sigma_m * p.sigma_m, 1e-15);
    assert_near(f[k].cov(5, 5), p.sigma_rad * p.sigma_rad, 1e-15);
  }
  assert_near(size_m.mean(), p.bias_m, 0.002);
  assert_near(angle.mean(), p.bias_rad, 0.002);
  // Consecutive fixes 0.67 s apart: the bias barely moves, the white noise
  // differences with sd sqrt(2) * white.
  assert_near(step.sd(), std::sqrt(2.0) * p.white_m, 0.15 * p.white_m);
  // Over minutes the direction turns.
  const Eigen::Vector3d first = f.front().error_p_m.normalized();
  double largest_turn = 0.0;
  for (const GpFix& g : f) {
    largest_turn =
        std::max(largest_turn, std::acos(std::min(1.0, first.dot(g.error_p_m.normalized()))));
  }
  assert_true(largest_turn > 60.0 * M_PI / 180.0);
}

void test_gp_jump_and_determinism(void**) {
  GpLocalizerParams p;
  p.dropout_probability = 0.0;
  SimGpLocalizer a(p, 21), b(p, 21);
  const std::vector<GpFix> fa = run_gp(a, 20.0), fb = run_gp(b, 20.0);
  assert_int_equal(fa.size(), fb.size());
  for (std::size_t k = 0; k < fa.size(); ++k) {
    assert_true(fa[k].T_world_body.matrix() == fb[k].T_world_body.matrix());
  }
  const Eigen::Vector3d before = a.bias_p_m();
  a.jump_by(Eigen::Vector3d(0.2, 0.0, 0.0));
  const std::vector<GpFix> after = run_gp(a, 5.0, Eigen::Isometry3d::Identity(), 20.01);
  assert_true(!after.empty());
  assert_near(after.back().error_p_m.x() - before.x(), 0.2, 0.025);
}

}  // namespace

int main() {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_imu_rate_jitter_and_white_noise_at_rest),
      cmocka_unit_test(test_imu_bias_random_walk_spreads_as_sqrt_time),
      cmocka_unit_test(test_imu_samples_integrate_back_to_the_motion),
      cmocka_unit_test(test_imu_saturates_and_flags),
      cmocka_unit_test(test_imu_same_seed_same_samples),
      cmocka_unit_test(test_imu_stalled_tick_drops_and_counts),
      cmocka_unit_test(test_gp_rate_latency_and_dropouts),
      cmocka_unit_test(test_gp_bias_size_drift_and_white_noise),
      cmocka_unit_test(test_gp_jump_and_determinism),
  };
  return cmocka_run_group_tests(tests, nullptr, nullptr);
}
