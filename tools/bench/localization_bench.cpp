// Google Benchmark: the localization filter's steps, one core, on a robot
// holding still 0.78 m in front of a handrail (the work per step does not
// depend on the motion). Run from the build tree:
//   tools/bench/localization_bench --benchmark_repetitions=5
//       --benchmark_report_aggregates_only=true  (one line)
//   ImuPropagation             one IMU sample: propagation and its history entry
//   GpPoseDelayed300ms         a GP pose 300 ms late: the update at its capture
//                              time and the re-propagation over 19 samples
//   GpPoseDelayed300msHandrail the same with handrail updates at 5 Hz in the
//                              window, re-applied on the way
//   HandrailUpdate/BE, /NE     a handrail measurement with 60 features (40 bar,
//                              20 wall) at the newest sample: thinning to 12,
//                              the per-feature gate, the stacked Joseph update
//   HandrailUpdateDelayed100ms/BE, /NE   the same 100 ms late (6 samples)
// The untimed IMU samples between the timed updates are paused out.
#include <benchmark/benchmark.h>

#include <Eigen/Geometry>
#include <memory>

#include "estimator/localization/localization_filter.hpp"

namespace {

using namespace estimator::localization;
using estimator::HandrailState;

constexpr std::int64_t kImuPeriodUs = 16000;  // 62.5 Hz

// The world of the tests: wall x = 0, vertical handrail centred 0.061 m off
// it, the body 1 m out facing away from it (the camera looks back at it).
struct World {
  Eigen::Isometry3d T_world_body = Eigen::Isometry3d::Identity();
  Eigen::Isometry3d T_world_handrail = Eigen::Isometry3d::Identity();
  Eigen::Isometry3d T_body_cam = default_T_body_cam();
  World() {
    T_world_body.translation() = Eigen::Vector3d(1.0, 0.0, -0.06);
    T_world_handrail.translation() = Eigen::Vector3d(0.061, 0.0, 0.0);
  }
  // A detection with 40 bar and 20 wall features; NE puts the detected
  // origin 10 cm along the bar, as a detector without an end would.
  void detect(HandrailState state, std::int64_t t_us, HandrailMeasurement* m) const {
    const Eigen::Isometry3d T_cam_handrail =
        (T_world_body * T_body_cam).inverse() * T_world_handrail;
    m->capture_time_us = t_us;
    m->state = state;
    m->num_features = 0;
    Eigen::Isometry3d det = T_cam_handrail;
    if (state == HandrailState::kNoEnd) det.translate(Eigen::Vector3d(0.0, 0.0, 0.1));
    m->T_cam_handrail = det;
    Eigen::Vector3d pts[60];
    for (int i = 0; i < 40; ++i) {
      const double u = i / 39.0;
      pts[i] = T_cam_handrail * Eigen::Vector3d(0.0175, 0.008 * ((i % 3) - 1), -0.25 + 0.5 * u);
    }
    for (int i = 0; i < 20; ++i) {
      const double side = i % 2 ? 1.0 : -1.0;
      pts[40 + i] =
          T_cam_handrail * Eigen::Vector3d(-0.061, side * (0.04 + 0.01 * i), -0.3 + 0.03 * i);
    }
    add_features(pts, 40, FeatureKind::kBar, m);
    add_features(pts + 40, 20, FeatureKind::kWall, m);
  }
  GpPose gp(std::int64_t t_us) const {
    GpPose g;
    g.capture_time_us = t_us;
    g.p_world_body_m = T_world_body.translation();
    g.q_world_body = Eigen::Quaterniond(T_world_body.linear());
    g.cov = PoseCovariance::Identity() * (0.03 * 0.03);
    g.cov.bottomRightCorner<3, 3>() = Eigen::Matrix3d::Identity() * (0.026 * 0.026);
    return g;
  }
};

struct Rig {
  World world;
  std::unique_ptr<LocalizationFilter> f = std::make_unique<LocalizationFilter>();
  std::unique_ptr<HandrailMeasurement> m = std::make_unique<HandrailMeasurement>();
  std::int64_t t_us = 0;
  void imu() {
    ImuSample s;
    s.t_us = t_us += kImuPeriodUs;
    f->add_imu(s);
  }
  // Initialised from a GP pose, with the handrail map built from BE
  // sightings and a few seconds of updates behind it.
  explicit Rig(bool with_map) {
    for (int i = 0; i < 20; ++i) imu();
    f->add_gp_pose(world.gp(t_us));
    for (int i = 0; i < 300; ++i) {
      imu();
      if (i % 40 == 0) f->add_gp_pose(world.gp(t_us - 200000));
      if (with_map && i % 12 == 0) {
        world.detect(HandrailState::kBothEnds, t_us - 80000, m.get());
        f->add_handrail(*m);
      }
    }
  }
};

void BM_ImuPropagation(benchmark::State& state) {
  Rig rig(true);
  for (auto _ : state) {
    rig.imu();
    benchmark::DoNotOptimize(rig.f->state().p_world_body_m.data());
  }
  if (rig.f->check() != Health::kOk) state.SkipWithError("filter unhealthy");
}
BENCHMARK(BM_ImuPropagation)->Unit(benchmark::kMicrosecond);

void gp_delayed(benchmark::State& state, bool handrail) {
  Rig rig(handrail);
  int n = 0;
  for (auto _ : state) {
    state.PauseTiming();
    // 1.5 Hz of GP poses: 42 samples between them, handrail at 5 Hz.
    for (int i = 0; i < 42; ++i) {
      rig.imu();
      if (handrail && ++n % 12 == 0) {
        rig.world.detect(HandrailState::kBothEnds, rig.t_us - 80000, rig.m.get());
        rig.f->add_handrail(*rig.m);
      }
    }
    const GpPose g = rig.world.gp(rig.t_us - 300000);
    state.ResumeTiming();
    const UpdateStatus st = rig.f->add_gp_pose(g);
    if (st != UpdateStatus::kAccepted) {
      state.SkipWithError(to_string(st));
      break;
    }
  }
}
void BM_GpPoseDelayed300ms(benchmark::State& state) {
  gp_delayed(state, false);
}
BENCHMARK(BM_GpPoseDelayed300ms)->Unit(benchmark::kMicrosecond);
void BM_GpPoseDelayed300msHandrail(benchmark::State& state) {
  gp_delayed(state, true);
}
BENCHMARK(BM_GpPoseDelayed300msHandrail)->Unit(benchmark::kMicrosecond);

void handrail(benchmark::State& state, std::int64_t latency_us) {
  const HandrailState hs = state.range(0) ? HandrailState::kNoEnd : HandrailState::kBothEnds;
  state.SetLabel(estimator::to_string(hs));
  Rig rig(true);
  for (auto _ : state) {
    state.PauseTiming();
    // 5 Hz: 12 samples between frames.
    for (int i = 0; i < 12; ++i) rig.imu();
    rig.world.detect(hs, rig.t_us - latency_us, rig.m.get());
    state.ResumeTiming();
    const UpdateStatus st = rig.f->add_handrail(*rig.m);
    if (st != UpdateStatus::kAccepted) {
      state.SkipWithError(to_string(st));
      break;
    }
  }
}
void BM_HandrailUpdate(benchmark::State& state) {
  handrail(state, 0);
}
BENCHMARK(BM_HandrailUpdate)->Arg(0)->Arg(1)->Unit(benchmark::kMicrosecond);
void BM_HandrailUpdateDelayed100ms(benchmark::State& state) {
  handrail(state, 96000);
}
BENCHMARK(BM_HandrailUpdateDelayed100ms)->Arg(0)->Arg(1)->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();
