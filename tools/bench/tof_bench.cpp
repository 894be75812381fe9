// Google Benchmark: the raw time-of-flight path. Processing one raw frame
// into a depth frame on the robot's code (drivers/pico_flexx/tof; target
// median <= 3 ms for MODE_9 on one core) and rendering one raw frame in the
// simulator (sim_hal/tof_raw_renderer; target <= 10 ms for MODE_9), on a
// shipped cluttered scenario. Medians of ten repetitions.
#include <benchmark/benchmark.h>

#include <cstdio>
#include <cstdlib>
#include <string>

#include "sim_hal/scenario.hpp"
#include "sim_hal/tof_raw_renderer.hpp"
#include "tof/processor.hpp"

#ifndef HRP_SOURCE_DIR
#define HRP_SOURCE_DIR "."
#endif

namespace {

sim_hal::Scenario load(const char* name) {
  sim_hal::Scenario sc;
  std::string error;
  if (!sim_hal::load_scenario(std::string(HRP_SOURCE_DIR) + "/sim_hal/scenarios/" + name, &sc,
                              &error)) {
    std::fprintf(stderr, "%s\n", error.c_str());
    std::exit(1);
  }
  return sc;
}

std::uint32_t max_exposure_us(tof::Mode mode) {
  return mode == tof::Mode::kMode9 ? 2000 : 500;
}

// strand_filter false: the vendor's flying-pixel test alone, the
// processing before the second look (side by side with the default).
void BM_ProcessRawFrame(benchmark::State& state, tof::Mode mode, bool strand_filter) {
  const sim_hal::Scenario sc = load("table2-iss.json");
  const tof::Calibration cal = sim_hal::simulated_calibration(sim_hal::pico_flexx_intrinsics(), 7);
  sim_hal::RawRenderer renderer(sim_hal::pico_flexx_intrinsics(), sc.sensor, {}, cal);
  // A few frames of the approach, processed in turn.
  static tof::RawFrame raw[4];
  for (int k = 0; k < 4; ++k) {
    renderer.render(sc.scene, sc.T_world_cam[static_cast<std::size_t>(k) % sc.T_world_cam.size()],
                    mode, max_exposure_us(mode), sc.seed, static_cast<std::uint64_t>(k), &raw[k]);
  }
  tof::ProcessingConfig config;
  config.strand_filter = strand_filter;
  tof::Processor processor(cal, config);
  hal::DepthFrame depth;
  std::size_t f = 0;
  for (auto _ : state) {
    if (processor.process(raw[f++ % 4], &depth) != tof::ProcessStatus::kOk) {
      state.SkipWithError("processing failed");
      break;
    }
    benchmark::DoNotOptimize(depth.points);
  }
  state.counters["valid_fraction"] =
      static_cast<double>(processor.last_counts().of(tof::PixelState::kValid)) / tof::kPixels;
}

void BM_RenderRawFrame(benchmark::State& state, tof::Mode mode) {
  const sim_hal::Scenario sc = load("table2-iss.json");
  const tof::Calibration cal = sim_hal::simulated_calibration(sim_hal::pico_flexx_intrinsics(), 7);
  sim_hal::RawRenderer renderer(sim_hal::pico_flexx_intrinsics(), sc.sensor, {}, cal);
  static tof::RawFrame raw;
  std::uint64_t f = 0;
  for (auto _ : state) {
    renderer.render(sc.scene, sc.T_world_cam[f % sc.T_world_cam.size()], mode,
                    max_exposure_us(mode), sc.seed, f, &raw);
    ++f;
    benchmark::DoNotOptimize(raw.image(0));
  }
}

}  // namespace

BENCHMARK_CAPTURE(BM_ProcessRawFrame, mode9, tof::Mode::kMode9, true)
    ->Unit(benchmark::kMillisecond)
    ->Repetitions(10)
    ->DisplayAggregatesOnly(true);
BENCHMARK_CAPTURE(BM_ProcessRawFrame, mode9_vendor_flying_test_only, tof::Mode::kMode9, false)
    ->Unit(benchmark::kMillisecond)
    ->Repetitions(10)
    ->DisplayAggregatesOnly(true);
BENCHMARK_CAPTURE(BM_ProcessRawFrame, mode5, tof::Mode::kMode5, true)
    ->Unit(benchmark::kMillisecond)
    ->Repetitions(10)
    ->DisplayAggregatesOnly(true);
BENCHMARK_CAPTURE(BM_RenderRawFrame, mode9, tof::Mode::kMode9)
    ->Unit(benchmark::kMillisecond)
    ->Repetitions(10)
    ->DisplayAggregatesOnly(true);
BENCHMARK_CAPTURE(BM_RenderRawFrame, mode5, tof::Mode::kMode5)
    ->Unit(benchmark::kMillisecond)
    ->Repetitions(10)
    ->DisplayAggregatesOnly(true);

BENCHMARK_MAIN();
