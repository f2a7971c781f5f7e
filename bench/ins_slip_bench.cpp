// INS slip detection speed (issue 6 target: the 70 s Pathfinder log "well
// under a second"). The log is loaded once through the importer; the
// benchmarks time the estimator only, in the CLI's configurations.
#include <benchmark/benchmark.h>

#include <cstdlib>
#include <string>

#include "core/discrepancy/odometry/study.h"
#include "core/estimation/ins_slip/ins_slip.h"
#include "importers/log_file.h"
#include "importers/mapping.h"

namespace {

using namespace roverlab;

const log::Log& pathfinder() {
  static const log::Log lg = [] {
    const std::string root = ROVERLAB_SOURCE_DIR;
    io::LoadOptions o;
    o.mapping = io::load_mapping(root + "/resources/mappings/wvu_pathfinder.json");
    return io::load_log(root + "/tests/data/test17run.mat", o).log;
  }();
  return lg;
}

void run(benchmark::State& state, const estimation::InsSlipOptions& o) {
  const log::Log& lg = pathfinder();
  const double seconds = lg.stream("imu").duration();
  for (auto _ : state) {
    auto r = estimation::run_ins_slip(lg, o);
    benchmark::DoNotOptimize(r);
  }
  // Log seconds processed per wall-clock second.
  state.counters["x_real_time"] =
      benchmark::Counter(seconds * static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}

void BM_InsSlipDefault(benchmark::State& state) { run(state, {}); }  // aided + detector pass, smoothed
BENCHMARK(BM_InsSlipDefault)->Unit(benchmark::kMillisecond);

void BM_InsSlipForwardFilterOnly(benchmark::State& state) {
  estimation::InsSlipOptions o;
  o.smooth = false;
  o.odometry_aiding = false;
  run(state, o);
}
BENCHMARK(BM_InsSlipForwardFilterOnly)->Unit(benchmark::kMillisecond);

void BM_OdometryDiscrepancy(benchmark::State& state) {
  const log::Log& lg = pathfinder();
  for (auto _ : state) {
    auto r = analysis::study_odometry(lg);
    benchmark::DoNotOptimize(r);
  }
}
BENCHMARK(BM_OdometryDiscrepancy)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
