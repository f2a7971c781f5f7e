// Writing and reading a 10-minute, 1 kHz, 64-channel log (about 300 MB of
// doubles) in RoverLab's HDF5 format. Targets (issue 2): reading back in at
// most 1 s, using at most 1.5 times the raw size in memory.
//
//   build/bench/bench_log_io [--benchmark_filter=...] [ROVERLAB_BENCH_DIR=/tmp]
//
// Counters: raw_MB (payload), file_MB, read_MBps, mem_ratio (bytes allocated
// by the read, measured with mallinfo2, over the raw payload).
#include <benchmark/benchmark.h>
#include <malloc.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

#include "core/log/log.h"
#include "core/log/resample.h"
#include "importers/hdf5_log.h"
#include "importers/log_file.h"

namespace {

namespace fs = std::filesystem;
using namespace roverlab;

constexpr double kSeconds = 600.0;
constexpr double kRateHz = 1000.0;
constexpr int kChannels = 64;

std::string bench_path() {
  const char* dir = std::getenv("ROVERLAB_BENCH_DIR");
  return (fs::path(dir != nullptr ? dir : fs::temp_directory_path().c_str()) /
          ("roverlab-bench-" + std::to_string(::getpid()) + ".h5"))
      .string();
}

log::Log make_log() {
  log::Log lg;
  lg.metadata.description = "benchmark: 10 min, 1 kHz, 64 channels";
  std::vector<double> t = log::uniform_times(0.0, kSeconds - 1.0 / kRateHz, kRateHz);
  log::Stream s("imu", t);
  for (int c = 0; c < kChannels; ++c) {
    std::vector<double> v(t.size());
    for (std::size_t i = 0; i < v.size(); ++i) v[i] = static_cast<double>(c) + 1e-3 * static_cast<double>(i % 1000);
    s.add_channel("ch" + std::to_string(c), "m/s^2", std::move(v));
  }
  lg.add_stream(std::move(s));
  return lg;
}

std::size_t allocated_bytes() {
  const struct mallinfo2 m = mallinfo2();
  return m.uordblks + m.hblkhd;
}

void BM_WriteLog(benchmark::State& state) {
  const log::Log lg = make_log();
  const std::string path = bench_path();
  for (auto _ : state) io::write_hdf5_log(lg, path);
  const double raw = static_cast<double>(lg.payload_bytes());
  state.counters["raw_MB"] = raw / 1e6;
  state.counters["file_MB"] = static_cast<double>(fs::file_size(path)) / 1e6;
  state.counters["write_MBps"] = benchmark::Counter(raw / 1e6, benchmark::Counter::kIsIterationInvariantRate);
  fs::remove(path);
}
BENCHMARK(BM_WriteLog)->Unit(benchmark::kMillisecond)->Iterations(3)->UseRealTime();

// Reads the bench log with `read` every iteration: time, memory over the raw payload.
template <class Read>
void read_whole_log(benchmark::State& state, Read&& read) {
  const std::string path = bench_path();
  double raw = 0.0;
  {
    const log::Log lg = make_log();
    raw = static_cast<double>(lg.payload_bytes());
    io::write_hdf5_log(lg, path);
  }
  double worst_ratio = 0.0;
  for (auto _ : state) {
    const std::size_t before = allocated_bytes();
    auto back = read(path);
    const std::size_t after = allocated_bytes();
    worst_ratio = std::max(worst_ratio, static_cast<double>(after - before) / raw);
    benchmark::DoNotOptimize(back);
  }
  state.counters["raw_MB"] = raw / 1e6;
  state.counters["mem_ratio"] = worst_ratio;
  state.counters["read_MBps"] = benchmark::Counter(raw / 1e6, benchmark::Counter::kIsIterationInvariantRate);
  fs::remove(path);
}

void BM_ReadLog(benchmark::State& state) {
  read_whole_log(state, [](const std::string& path) { return io::read_hdf5_log(path); });
}
BENCHMARK(BM_ReadLog)->Unit(benchmark::kMillisecond)->Iterations(5)->UseRealTime();

// What a user's open costs: load_log tries an HDF5 file in a child process
// first (libhdf5 may crash on a damaged file), then reads it.
void BM_LoadLogInChild(benchmark::State& state) {
  read_whole_log(state, [](const std::string& path) { return io::load_log(path); });
}
BENCHMARK(BM_LoadLogInChild)->Unit(benchmark::kMillisecond)->Iterations(5)->UseRealTime();

// The same read from disk rather than the page cache: the cache is dropped
// before every iteration (needs root; skipped otherwise).
bool drop_page_cache() {
  ::sync();
  FILE* f = std::fopen("/proc/sys/vm/drop_caches", "w");
  if (f == nullptr) return false;
  const bool ok = std::fputs("3\n", f) >= 0;
  return std::fclose(f) == 0 && ok;
}

void BM_ReadLogCold(benchmark::State& state) {
  const std::string path = bench_path();
  double raw = 0.0;
  {
    const log::Log lg = make_log();
    raw = static_cast<double>(lg.payload_bytes());
    io::write_hdf5_log(lg, path);
  }
  for (auto _ : state) {
    state.PauseTiming();
    const bool dropped = drop_page_cache();
    state.ResumeTiming();
    if (!dropped) {
      state.SkipWithError("cannot drop the page cache (needs root)");
      break;
    }
    log::Log back = io::read_hdf5_log(path);
    benchmark::DoNotOptimize(back);
  }
  state.counters["read_MBps"] = benchmark::Counter(raw / 1e6, benchmark::Counter::kIsIterationInvariantRate);
  fs::remove(path);
}
BENCHMARK(BM_ReadLogCold)->Unit(benchmark::kMillisecond)->Iterations(3)->UseRealTime();

// Reading one channel alone: what the chunked layout buys a plot.
void BM_ReadOneChannel(benchmark::State& state) {
  const std::string path = bench_path();
  io::write_hdf5_log(make_log(), path);
  io::Hdf5LogReader reader(path);
  for (auto _ : state) {
    auto v = reader.read_channel("imu", "ch17");
    benchmark::DoNotOptimize(v);
  }
  fs::remove(path);
}
BENCHMARK(BM_ReadOneChannel)->Unit(benchmark::kMillisecond)->Iterations(10)->UseRealTime();

}  // namespace

// A CSV log 200,000 columns wide and 3 rows long (4.7 MB): reading is linear
// in the columns (shared/robustness/findings.md F9: more than 60 s before the
// channels were indexed by name; target 2 s).
void BM_ReadWideCsv(benchmark::State& state) {
  const std::string path = bench_path() + ".csv";
  {
    std::FILE* out = std::fopen(path.c_str(), "w");
    std::fputs("time [s]", out);
    for (int k = 0; k < 200000; ++k) std::fprintf(out, ",c%d [m]", k);
    for (int row = 0; row < 3; ++row) {
      std::fprintf(out, "\n%d", row);
      for (int k = 0; k < 200000; ++k) std::fputs(",1.5", out);
    }
    std::fputs("\n", out);
    std::fclose(out);
  }
  for (auto _ : state) {
    io::LoadedLog back = io::load_log(path);
    benchmark::DoNotOptimize(back);
  }
  fs::remove(path);
}
BENCHMARK(BM_ReadWideCsv)->Unit(benchmark::kMillisecond)->Iterations(3)->UseRealTime();

BENCHMARK_MAIN();
