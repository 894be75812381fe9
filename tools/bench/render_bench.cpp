// Google Benchmark: the simulated Pico Flexx rendering one 224 x 171 frame
// of a shipped cluttered scenario with every ToF effect on.
#include <benchmark/benchmark.h>

#include <cstdio>
#include <cstdlib>
#include <string>

#include "sim_hal/scenario.hpp"
#include "sim_hal/tof_sensor.hpp"

#ifndef HRP_SOURCE_DIR
#define HRP_SOURCE_DIR "."
#endif

namespace {

void BM_RenderFrame(benchmark::State& state, const char* scenario_name) {
  sim_hal::Scenario sc;
  std::string error;
  if (!sim_hal::load_scenario(std::string(HRP_SOURCE_DIR) + "/sim_hal/scenarios/" + scenario_name,
                              &sc, &error)) {
    std::fprintf(stderr, "%s\n", error.c_str());
    std::exit(1);
  }
  sim_hal::DepthRenderer renderer(sim_hal::pico_flexx_intrinsics(), sc.sensor);
  std::vector<hal::DepthPoint> points;
  std::uint64_t f = 0;
  for (auto _ : state) {
    renderer.render(sc.scene, sc.T_world_cam[f % sc.T_world_cam.size()], sc.seed, f, &points);
    ++f;
    benchmark::DoNotOptimize(points.data());
  }
}

}  // namespace

BENCHMARK_CAPTURE(BM_RenderFrame, table2_iss, "table2-iss.json")->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_RenderFrame, table2_iss_mesh, "table2-iss-mesh.json")
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_RenderFrame, sweep, "sweep.json")->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_RenderFrame, clutter_only, "clutter-only.json")->Unit(benchmark::kMillisecond);
// A rack wall, rack clutter, and the Columbus module's mesh.
BENCHMARK_CAPTURE(BM_RenderFrame, rack_table2_21_5, "rack-table2-iss-mesh-21-5.json")
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_RenderFrame, rack_clutter_vertical_30, "rack-clutter-vertical-30.json")
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_RenderFrame, columbus_approaches, "columbus-approaches.json")
    ->Unit(benchmark::kMillisecond);

BENCHMARK_MAIN();
