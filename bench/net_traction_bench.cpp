// Net-traction estimators speed (issue 12 target: Estimators 1, 2 and 3, three
// UKFs, over a 200 s 50 Hz log in <= 0.3 s on one core). The log is the
// rolling terrain with soil strength x2.5 (a full traverse), simulated once
// outside the timed loop.
#include <benchmark/benchmark.h>

#include <string>

#include "core/estimation/net_traction/net_traction.h"
#include "core/estimation/net_traction/surface.h"
#include "core/simulation/rocker_bogie.h"
#include "importers/soil_file.h"

namespace {

using namespace roverlab;

const log::Log& rolling_log() {
  static const log::Log lg = [] {
    simulation::RockerBogieRun r;
    r.soil = io::load_soil(std::string(ROVERLAB_SOURCE_DIR) + "/resources/soils/ding_tyii.json");
    r.effects.soil_strength = 2.5;
    r.duration = 200.0;
    return simulation::simulate_rocker_bogie({}, {}, r).log;
  }();
  return lg;
}

void BM_ThreeEstimators200s(benchmark::State& state) {
  const log::Log& lg = rolling_log();
  estimation::NetTractionOptions o;
  o.force_sensors = estimation::ForceSensors::two_axis;
  o.compare_single_axis = true;  // Estimators 1, 2 and 3
  for (auto _ : state) {
    auto r = estimation::run_net_traction(lg, {}, o);
    benchmark::DoNotOptimize(r);
  }
  state.counters["x_real_time"] =
      benchmark::Counter(200.0 * static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_ThreeEstimators200s)->Unit(benchmark::kMillisecond)->Iterations(5)->UseRealTime();

// Single-axis sensors' second pass (`--bogie-split shape`, the default):
// the order-2 DP surface of the first pass's points, then Estimators 1 and 3
// again with the shape split. Not part of the three-UKF target; it adds to
// `estimate net-traction`'s time.
void BM_SingleAxisSecondPass200s(benchmark::State& state) {
  const log::Log& lg = rolling_log();
  const estimation::NetTractionResult first = estimation::run_net_traction(lg, {}, {});
  for (auto _ : state) {
    auto r = analysis::single_axis_second_pass(lg, {}, {}, first, {});
    benchmark::DoNotOptimize(r);
  }
}
BENCHMARK(BM_SingleAxisSecondPass200s)->Unit(benchmark::kMillisecond)->Iterations(5)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
