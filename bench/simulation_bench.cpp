// Rocker-bogie simulation speed (issue 5 targets: the 200 s rolling-terrain
// run in <= 2 s with the polynomial traction surrogate and <= 20 s with the
// full Wong-Reece model, one core).
#include <benchmark/benchmark.h>

#include <string>

#include "core/simulation/rocker_bogie.h"
#include "importers/soil_file.h"

namespace {

using namespace roverlab;

void run(benchmark::State& state, simulation::TractionSource traction) {
  simulation::RockerBogieRun r;
  r.soil = io::load_soil(std::string(ROVERLAB_SOURCE_DIR) + "/resources/soils/ding_tyii.json");
  r.traction = traction;
  r.duration = 200.0;
  for (auto _ : state) {
    auto out = simulation::simulate_rocker_bogie({}, {}, r);
    benchmark::DoNotOptimize(out);
  }
  state.counters["x_real_time"] =
      benchmark::Counter(200.0 * static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}

void BM_RollingTerrain200sPolynomial(benchmark::State& s) { run(s, simulation::TractionSource::polynomial); }
BENCHMARK(BM_RollingTerrain200sPolynomial)->Unit(benchmark::kSecond)->Iterations(3)->UseRealTime();

void BM_RollingTerrain200sWongReece(benchmark::State& s) { run(s, simulation::TractionSource::wong_reece); }
BENCHMARK(BM_RollingTerrain200sWongReece)->Unit(benchmark::kSecond)->Iterations(1)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
