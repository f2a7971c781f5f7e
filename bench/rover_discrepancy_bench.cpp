// The rover discrepancy study (issue 13) on a 200 s, 50 Hz planar
// rocker-bogie log: target at most 20 s on one core (docs/performance.md).
#include <benchmark/benchmark.h>

#include "core/discrepancy/rover/study.h"
#include "importers/soil_file.h"

using namespace roverlab;

namespace {

analysis::RoverScenarioModel model() {
  analysis::RoverScenarioModel m;
  m.name = "flat 200 s";
  m.rover = "kapvik_planar";
  m.run.soil = io::load_soil(std::string(ROVERLAB_SOURCE_DIR) + "/resources/soils/ding_tyii.json");
  m.run.path = simulation::flat_path();
  m.run.duration = 200;
  return m;
}

void study(benchmark::State& state, const std::vector<std::pair<std::string, double>>& effects) {
  const analysis::RoverScenarioModel m = model();
  simulation::RockerBogieRun run = m.run;
  for (const auto& e : effects) simulation::set_effect(run.effects, e.first, e.second);
  const log::Log lg = simulation::simulate_rocker_bogie(m.geometry, m.parameters, run).log;
  int simulations = 0;
  for (auto _ : state) {
    const auto r = analysis::study_rover(lg, m);
    simulations = r.simulations;
    benchmark::DoNotOptimize(r.verdict);
  }
  state.counters["simulations"] = simulations;
}

void BM_RoverStudyNoEffect(benchmark::State& state) { study(state, {}); }
void BM_RoverStudySoilChange(benchmark::State& state) {
  study(state, {{"soil-strength", 0.8}, {"effect-start-x", 1.5}});
}
void BM_RoverStudySlipSinkageAndGyroBias(benchmark::State& state) {
  study(state, {{"slip-sinkage", 0.3}, {"gyro-bias", 0.002}});
}

}  // namespace

BENCHMARK(BM_RoverStudyNoEffect)->Unit(benchmark::kSecond)->Iterations(1);
BENCHMARK(BM_RoverStudySoilChange)->Unit(benchmark::kSecond)->Iterations(1);
BENCHMARK(BM_RoverStudySlipSinkageAndGyroBias)->Unit(benchmark::kSecond)->Iterations(1);
BENCHMARK_MAIN();
