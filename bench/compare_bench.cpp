// Comparing two one-hour runs at 100 Hz with 40 channels each (issue 45):
// target at most 2 s of CPU and at most 2x the two logs' size in memory.
//
//   build/bench/bench_compare
//
// Counters: logs_MB (the two logs' payload), peak_ratio (the process's peak
// resident memory during the comparison, VmHWM after resetting it through
// /proc/self/clear_refs, over the two logs' payload; the logs themselves
// count, so 2 means the comparison added one logs' worth), channels, differ
// (the 12 wheel channels should), offset_s (2.5 should be found).
#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <random>
#include <string>

#include "core/comparison/compare.h"
#include "core/log/resample.h"

namespace {

using namespace roverlab;

constexpr double kSeconds = 3600.0;
constexpr double kRateHz = 100.0;

// Streams of 6, 10, 12 and 12 channels (40): smooth signals plus noise, the
// second run's clock 2.5 s later and its wheel channels 10 % higher.
log::Log make_run(unsigned seed, double clock_shift, double wheel_scale) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0.0, 0.01);
  log::Log lg;
  const std::pair<const char*, int> streams[] = {{"imu", 6}, {"joints", 10}, {"wheels", 12}, {"forces", 12}};
  for (const auto& [name, channels] : streams) {
    std::vector<double> t = log::uniform_times(0.0, kSeconds, kRateHz);
    for (double& v : t) v += clock_shift;
    log::Stream s(name, t);
    for (int c = 0; c < channels; ++c) {
      std::vector<double> x(t.size());
      const double scale = std::string(name) == "wheels" ? wheel_scale : 1.0;
      for (std::size_t k = 0; k < x.size(); ++k) {
        const double u = static_cast<double>(k) / kRateHz;
        x[k] = scale * (std::sin(0.05 * u * (c + 1)) + 0.3 * std::sin(1.3 * u + c) * std::cos(0.011 * u)) + noise(rng);
      }
      s.add_channel("c" + std::to_string(c), "1", std::move(x));
    }
    lg.add_stream(std::move(s));
  }
  return lg;
}

double resident_peak_bytes() {
  std::ifstream status("/proc/self/status");
  std::string key;
  double kb = NAN;
  while (status >> key) {
    if (key == "VmHWM:") {
      status >> kb;
      break;
    }
  }
  return kb * 1024.0;
}

void reset_resident_peak() { std::ofstream("/proc/self/clear_refs") << "5"; }

void BM_CompareTwoOneHourRuns(benchmark::State& state) {
  const log::Log base = make_run(1, 0.0, 1.0);
  const log::Log other = make_run(2, 2.5, state.range(0) != 0 ? 1.1 : 1.0);
  const double logs = static_cast<double>(base.payload_bytes() + other.payload_bytes());
  comparison::CompareOptions options;
  options.keep_differences = state.range(1) != 0;
  options.alignment.find_offset = true;  // the 2.5 s found by cross-correlation, the costliest alignment
  double peak = 0;
  std::size_t differ = 0, channels = 0;
  double offset = 0;
  for (auto _ : state) {
    reset_resident_peak();
    const comparison::RunComparison r = comparison::compare_runs(base, other, options);
    peak = std::max(peak, resident_peak_bytes());
    differ = r.differing();
    offset = r.alignment.offset_s;
    channels = r.channels.size();
    benchmark::DoNotOptimize(r);
  }
  state.counters["logs_MB"] = logs / 1e6;
  state.counters["peak_ratio"] = peak / logs;
  state.counters["channels"] = static_cast<double>(channels);
  state.counters["differ"] = static_cast<double>(differ);
  state.counters["offset_s"] = offset;
}
// Args: {wheel effect, keep the difference channels (-o)}.
BENCHMARK(BM_CompareTwoOneHourRuns)->Args({1, 0})->Args({1, 1})->Unit(benchmark::kMillisecond)->Iterations(3);

}  // namespace

BENCHMARK_MAIN();
