// Google Benchmark: parsing JSON documents of the shapes hostile or large
// input takes (many keys in one object, a long array of numbers, a shipped
// configuration), reported per MB so that "well under a second per MB"
// can be read off directly (bytes_per_second).
#include <benchmark/benchmark.h>

#include <cstdio>
#include <cstdlib>
#include <string>

#include "formats/json.hpp"
#include "formats/text_file.hpp"

namespace {

std::string object_of_keys(int keys) {
  std::string text = "{";
  for (int k = 0; k < keys; ++k) {
    if (k) text += ",\n";
    text += "\"key" + std::to_string(k) + "\": " + std::to_string(k * 0.5);
  }
  return text + "}";
}

std::string array_of_numbers(std::size_t bytes) {
  std::string text = "[0";
  while (text.size() < bytes) text += ",1.25,-300,7";
  return text + "]";
}

void parse(benchmark::State& state, const std::string& text) {
  formats::JsonValue v;
  std::string error;
  for (auto _ : state) {
    if (!formats::parse_json(text, &v, &error)) {
      state.SkipWithError(error.c_str());
      break;
    }
    benchmark::DoNotOptimize(v.type);
  }
  state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations()) *
                          static_cast<std::int64_t>(text.size()));
  state.counters["MB"] = static_cast<double>(text.size()) / (1024.0 * 1024.0);
}

void BM_ParseObjectOfKeys(benchmark::State& state) {
  parse(state, object_of_keys(static_cast<int>(state.range(0))));
}
BENCHMARK(BM_ParseObjectOfKeys)->Arg(80000)->Unit(benchmark::kMillisecond);

void BM_ParseArrayOfNumbers(benchmark::State& state) {
  parse(state, array_of_numbers(static_cast<std::size_t>(state.range(0))));
}
BENCHMARK(BM_ParseArrayOfNumbers)->Arg(1 << 20)->Arg(3 << 20)->Unit(benchmark::kMillisecond);

void BM_ParseShippedConfiguration(benchmark::State& state) {
  std::string text, error;
  const std::string path = std::string(HRP_SOURCE_DIR) + "/fsw_app/config/fsw_app.json";
  if (formats::read_file_bounded(path, formats::kMaxTextFileBytes, &text, &error) !=
      formats::FileStatus::kOk) {
    std::fprintf(stderr, "%s\n", error.c_str());
    std::exit(1);
  }
  parse(state, text);
}
BENCHMARK(BM_ParseShippedConfiguration)->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();
