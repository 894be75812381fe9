// Google Benchmark: the detector per stage and per frame, on recorded
// simulator frames (tests/data), one core. Run from the build tree:
//   tools/bench/estimator_bench [--benchmark_repetitions=5]
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <string>
#include <vector>

#include "estimator/handrail_detector.hpp"
#include "estimator/handrail_filters.hpp"
#include "estimator/line_estimation.hpp"
#include "estimator/plane_estimation.hpp"
#include "formats/pcd_io.hpp"
#include "frame_convert.hpp"
#include "sim_hal/camera_model.hpp"
#include "sim_hal/scenario.hpp"
#include "sim_hal/tof_sensor.hpp"

#ifndef HRP_SOURCE_DIR
#define HRP_SOURCE_DIR "."
#endif

namespace {

struct Frame {
  std::vector<estimator::CloudPoint> points;
  estimator::OrganizedCloud cloud;
  estimator::DetectorConfig cfg;
};

const Frame& frame(const char* name, bool round) {
  static std::vector<Frame*> cache;
  static std::vector<std::string> names;
  for (std::size_t k = 0; k < names.size(); ++k)
    if (names[k] == name) return *cache[k];
  formats::PcdFrame pcd;
  std::string error;
  if (!formats::read_pcd(std::string(HRP_SOURCE_DIR) + "/tests/data/" + name, &pcd, &error)) {
    std::fprintf(stderr, "%s\n", error.c_str());
    std::exit(1);
  }
  Frame* f = new Frame;
  f->cloud = tools::to_estimator_cloud(pcd.view(), &f->points);
  f->cfg.gripper_angle_rad = static_cast<float>(M_PI / 2);
  if (round) f->cfg.handrail = estimator::paper_round_handrail(0.55f);
  cache.push_back(f);
  names.push_back(name);
  return *f;
}

void BM_FrameProposed(benchmark::State& state, const char* name, bool round) {
  const Frame& f = frame(name, round);
  estimator::HandrailDetector det(f.cfg);
  std::uint64_t id = 0;
  for (auto _ : state) {
    estimator::OrganizedCloud c = f.cloud;
    c.frame_id = id++;  // fresh random numbers each frame, as live
    benchmark::DoNotOptimize(det.detect(c, estimator::Method::kProposed));
  }
}

// Every 10th frame of a shipped scenario (for Table 2: five frames of each
// of the eight poses), rendered once, so that a figure covers the spread
// of views rather than one frame.
struct ScenarioFrames {
  std::vector<std::vector<estimator::CloudPoint>> points;
  std::vector<estimator::OrganizedCloud> clouds;
  estimator::DetectorConfig cfg;
};

const ScenarioFrames& scenario_frames(const char* name, bool round) {
  static std::vector<std::pair<std::string, ScenarioFrames*>> cache;
  for (const auto& entry : cache)
    if (entry.first == name) return *entry.second;
  sim_hal::Scenario sc;
  std::string error;
  if (!sim_hal::load_scenario(std::string(HRP_SOURCE_DIR) + "/sim_hal/scenarios/" + name, &sc,
                              &error)) {
    std::fprintf(stderr, "%s\n", error.c_str());
    std::exit(1);
  }
  sim_hal::DepthRenderer renderer(sim_hal::pico_flexx_intrinsics(), sc.sensor);
  auto* frames = new ScenarioFrames;
  frames->cfg.gripper_angle_rad = static_cast<float>(sc.gripper_angle_deg * M_PI / 180.0);
  if (round) frames->cfg.handrail = estimator::paper_round_handrail(0.55f);
  std::vector<hal::DepthPoint> rendered;
  for (std::size_t f = 0; f < sc.T_world_cam.size(); f += 10) {
    renderer.render(sc.scene, sc.T_world_cam[f], sc.seed, f, &rendered);
    hal::DepthFrame view;
    view.frame_id = f;
    view.width = renderer.camera().width;
    view.height = renderer.camera().height;
    view.points = rendered.data();
    frames->points.emplace_back();
    frames->clouds.push_back(tools::to_estimator_cloud(view, &frames->points.back()));
  }
  cache.emplace_back(name, frames);
  return *frames;
}

// This thread's CPU time: on a shared virtual machine the wall clock also
// counts the time the hypervisor gave the core to someone else (steal),
// which moves by tens of per cent from one minute to the next.
double thread_cpu_us() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return 1e6 * static_cast<double>(ts.tv_sec) + 1e-3 * static_cast<double>(ts.tv_nsec);
}

// Each iteration is one frame; besides the mean per iteration, the
// per-frame median and 90th percentile are reported as counters (the frames
// differ: the mean is pulled up by the heavy ones), in wall time and in the
// thread's CPU time.
// bay_budget: mounts searched in a view of an empty bay, 0 for the
// configuration's (5); 3, the earlier budget, beside it.
// faces_wall: the cross test's probes take the faces in view as wall (the
// the default); off beside it.
void BM_ScenarioProposed(benchmark::State& state, const char* name, bool round,
                         std::uint32_t bay_budget = 0, bool faces_wall = true,
                         bool bar_first = false) {
  const ScenarioFrames& frames = scenario_frames(name, round);
  estimator::DetectorConfig cfg = frames.cfg;
  if (bay_budget > 0) cfg.max_mount_hypotheses_bay = bay_budget;
  cfg.cross_faces_wall = faces_wall;
  cfg.bar_first = bar_first;
  estimator::HandrailDetector det(cfg);
  std::vector<double> frame_us, frame_cpu_us;
  frame_us.reserve(1 << 16);
  frame_cpu_us.reserve(1 << 16);
  std::size_t k = 0;
  for (auto _ : state) {
    const auto t0 = std::chrono::steady_clock::now();
    const double cpu0_us = thread_cpu_us();
    benchmark::DoNotOptimize(
        det.detect(frames.clouds[k % frames.clouds.size()], estimator::Method::kProposed));
    frame_cpu_us.push_back(thread_cpu_us() - cpu0_us);
    frame_us.push_back(
        std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - t0).count());
    ++k;
  }
  std::sort(frame_us.begin(), frame_us.end());
  std::sort(frame_cpu_us.begin(), frame_cpu_us.end());
  if (!frame_us.empty()) {
    state.counters["frame_median_us"] = frame_us[frame_us.size() / 2];
    state.counters["frame_p90_us"] = frame_us[frame_us.size() * 9 / 10];
    state.counters["frame_cpu_median_us"] = frame_cpu_us[frame_cpu_us.size() / 2];
  }
}

void BM_FrameBasic(benchmark::State& state, const char* name, bool round) {
  const Frame& f = frame(name, round);
  estimator::HandrailDetector det(f.cfg);
  std::uint64_t id = 0;
  for (auto _ : state) {
    estimator::OrganizedCloud c = f.cloud;
    c.frame_id = id++;
    benchmark::DoNotOptimize(det.detect(c, estimator::Method::kBasic));
  }
}

// The stages, each on the state the previous stages leave in the workspace.
struct StageSetup {
  const Frame& f;
  estimator::Workspace ws;
  estimator::Plane wall;
  estimator::PixelScale scale;
  explicit StageSetup(const Frame& fr) : f(fr), ws(fr.cloud.size()) {
    estimator::sample_valid_points(f.cloud, f.cfg, ws);
    estimator::Random rng(1);
    scale = estimator::estimate_pixel_scale(f.cloud, ws.sample);
    wall = estimator::estimate_plane(f.cloud, f.cfg, rng, ws).plane;
    std::uint32_t valid_pixels = 0;
    estimator::gap_distance_test(f.cloud, f.cfg, wall, ws, &valid_pixels);
    estimator::cross_point_test(f.cloud, f.cfg, wall, scale, ws);
    estimator::side_width_test(f.cloud, f.cfg, scale, ws);
    estimator::project_to_wall(f.cloud, wall, ws);
  }
};

void BM_Stage(benchmark::State& state, int stage) {
  static StageSetup* s = new StageSetup(frame("table2-iss-1.pcd", false));
  estimator::Random rng(2);
  for (auto _ : state) {
    switch (stage) {
      case 6:
        benchmark::DoNotOptimize(estimator::sample_valid_points(s->f.cloud, s->f.cfg, s->ws));
        break;
      case 0:
        benchmark::DoNotOptimize(estimator::estimate_pixel_scale(s->f.cloud, s->ws.sample));
        break;
      case 1:
        benchmark::DoNotOptimize(estimator::estimate_plane(s->f.cloud, s->f.cfg, rng, s->ws));
        break;
      case 7: {
        // The same without the faces' normal (plane_faces_normal off, the
        // the earlier default): what that step costs.
        static const estimator::DetectorConfig broad_cfg = [] {
          estimator::DetectorConfig c = s->f.cfg;
          c.plane_faces_normal = false;
          return c;
        }();
        benchmark::DoNotOptimize(estimator::estimate_plane(s->f.cloud, broad_cfg, rng, s->ws));
        break;
      }
      case 2: {
        std::uint32_t valid_pixels = 0;
        benchmark::DoNotOptimize(
            estimator::gap_distance_test(s->f.cloud, s->f.cfg, s->wall, s->ws, &valid_pixels));
        break;
      }
      case 3:
        estimator::cross_point_test(s->f.cloud, s->f.cfg, s->wall, s->scale, s->ws);
        break;
      case 4:
        estimator::side_width_test(s->f.cloud, s->f.cfg, s->scale, s->ws);
        break;
      case 5: {
        estimator::LineModel c[2];
        estimator::estimate_handrail_candidates(s->f.cloud, s->f.cfg, s->wall, rng, s->ws,
                                                s->ws.side, c);
        benchmark::DoNotOptimize(c);
        break;
      }
    }
  }
}

}  // namespace

BENCHMARK_CAPTURE(BM_FrameProposed, iss_table2_1, "table2-iss-1.pcd", false)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_FrameProposed, round_table2_2, "table2-round-2.pcd", true)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_FrameProposed, clutter_only, "clutter-only-0.pcd", false)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_ScenarioProposed, table2_iss, "table2-iss.json", false)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_ScenarioProposed, table2_round, "table2-round.json", true)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_ScenarioProposed, clutter_only, "clutter-only.json", false)
    ->Unit(benchmark::kMillisecond);
// The station's rack walls (every 10th frame of each scenario).
BENCHMARK_CAPTURE(BM_ScenarioProposed, rack_table2_21_5, "rack-table2-iss-mesh-21-5.json", false)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_ScenarioProposed, rack_table2_0_76, "rack-table2-iss-0-76.json", false)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_ScenarioProposed, rack_approach_vertical_21_5,
                  "rack-approach-vertical-21-5.json", false)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_ScenarioProposed, rack_clutter_vertical_30, "rack-clutter-vertical-30.json",
                  false)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_ScenarioProposed, rack_clutter_vertical_30_no_faces_wall,
                  "rack-clutter-vertical-30.json", false, 0, false)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_ScenarioProposed, rack_no_handrail_wall, "rack-no-handrail-wall.json", false)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_ScenarioProposed, rack_no_handrail_wall_no_faces_wall,
                  "rack-no-handrail-wall.json", false, 0, false)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_ScenarioProposed, columbus_approaches, "columbus-approaches.json", false)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_ScenarioProposed, columbus_approaches_bay_budget_3, "columbus-approaches.json",
                  false, 3)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_ScenarioProposed, columbus_approaches_no_faces_wall,
                  "columbus-approaches.json", false, 0, false)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_ScenarioProposed, rack_table2_0_53, "rack-table2-iss-0-53.json", false)
    ->Unit(benchmark::kMillisecond);
// The node and Cupola meshes (every 10th frame of their views).
BENCHMARK_CAPTURE(BM_ScenarioProposed, node1_views, "node1-views.json", false)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_ScenarioProposed, node2_views, "node2-views.json", false)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_ScenarioProposed, node3_views, "node3-views.json", false)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_ScenarioProposed, cupola_views, "cupola-views.json", false)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_ScenarioProposed, rack_table2_0_53_bay_budget_3, "rack-table2-iss-0-53.json",
                  false, 3)
    ->Unit(benchmark::kMillisecond);
// The same scenes bar first (DetectorConfig::bar_first).
BENCHMARK_CAPTURE(BM_ScenarioProposed, table2_iss_bar_first, "table2-iss.json", false, 0, true,
                  true)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_ScenarioProposed, clutter_only_bar_first, "clutter-only.json", false, 0, true,
                  true)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_ScenarioProposed, rack_table2_0_53_bar_first, "rack-table2-iss-0-53.json",
                  false, 0, true, true)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_ScenarioProposed, columbus_approaches_bar_first, "columbus-approaches.json",
                  false, 0, true, true)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_ScenarioProposed, node1_views_bar_first, "node1-views.json", false, 0, true,
                  true)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_ScenarioProposed, node2_views_bar_first, "node2-views.json", false, 0, true,
                  true)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_ScenarioProposed, node3_views_bar_first, "node3-views.json", false, 0, true,
                  true)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_ScenarioProposed, cupola_views_bar_first, "cupola-views.json", false, 0, true,
                  true)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_FrameBasic, iss_table2_1, "table2-iss-1.pcd", false)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Stage, sample_valid_points, 6)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_Stage, pixel_scale, 0)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_Stage, plane_estimation, 1)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_Stage, plane_estimation_broad_only, 7)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_Stage, gap_distance_test, 2)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_Stage, cross_point_test, 3)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_Stage, side_width_test, 4)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_Stage, handrail_candidates, 5)->Unit(benchmark::kMicrosecond);

BENCHMARK_MAIN();
