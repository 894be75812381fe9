// Google Benchmark: one READ of an AX-12A's present position at 1 Mbps,
// round trip through the real driver and termios code to a simulated servo
// on a pseudo-terminal (return delay 0, as on the robot). Reports the
// median and the 99th percentile of the round trip as counters.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include "dynamixel/ax12.hpp"
#include "dynamixel/bus.hpp"
#include "hal/linux_serial_port.hpp"
#include "sim_hal/sim_servo_bus.hpp"

namespace {

void BM_ReadPresentPosition(benchmark::State& state) {
  sim_hal::SimServoBus sim({1, 2});
  std::string error;
  hal::MonotonicClock clock;
  hal::LinuxSerialPort port;
  if (!sim.start(&error) || port.open(sim.path(), 1000000, &error) != hal::SerialStatus::kOk) {
    std::fprintf(stderr, "%s\n", error.c_str());
    std::exit(1);
  }
  dynamixel::Bus bus(port, clock);
  // Return delay 0 on the servo and in the bus's timing, as configured on
  // the robot for the shortest round trip.
  bus.write_u8(1, dynamixel::ax12::kReturnDelay, 0);
  std::vector<double> round_trip_us;
  round_trip_us.reserve(100000);
  std::size_t failures = 0;
  for (auto _ : state) {
    const std::int64_t t0 = clock.now_us();
    std::uint16_t units = 0;
    const dynamixel::BusResult r = bus.read_u16(1, dynamixel::ax12::kPresentPosition, &units);
    round_trip_us.push_back(static_cast<double>(clock.now_us() - t0));
    failures += r.ok() ? 0 : 1;
    benchmark::DoNotOptimize(units);
  }
  std::sort(round_trip_us.begin(), round_trip_us.end());
  if (!round_trip_us.empty()) {
    state.counters["median_us"] = round_trip_us[round_trip_us.size() / 2];
    state.counters["p99_us"] = round_trip_us[round_trip_us.size() * 99 / 100];
  }
  state.counters["failures"] = static_cast<double>(failures);
}

}  // namespace

BENCHMARK(BM_ReadPresentPosition)->Unit(benchmark::kMicrosecond)->MinTime(2.0);

BENCHMARK_MAIN();
