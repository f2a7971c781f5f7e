// Wong-Reece evaluation speed (issue 3 targets): one evaluation with the root
// solve, Simpson <= 2 us and 500-point Riemann <= 300 us; a 100 x 100
// traction grid <= 50 ms (Simpson), all on one core. The single-wheel
// discrepancy study on 5,000 testbed rows in under 10 s (issue 17), linear in
// the rows.
#include <benchmark/benchmark.h>

#include <cmath>
#include <random>

#include "core/discrepancy/single_wheel/study.h"
#include "core/terramechanics/model.h"
#include "core/terramechanics/rft.h"
#include "core/terramechanics/traction_surface.h"
#include "importers/soil_file.h"
#include "importers/wheel_test_csv.h"
#include "tests/support/resampled_wheel_test.h"

namespace {

using namespace roverlab::terramechanics;

// Seed 003 Table 2.2, from resources/soils/ding_tyii.json.
Soil tyii() {
  static const Soil soil = roverlab::io::load_soil(ROVERLAB_SOURCE_DIR "/resources/soils/ding_tyii.json");
  return soil;
}

void BM_WongReeceSimpson(benchmark::State& state) {
  const Soil soil = tyii();
  const Wheel wheel{0.075, 0.07, 0, 0.0};
  ModelOptions o;
  int i = 0;
  for (auto _ : state) {
    // Loads 1..200 N and slips 0..0.99: the root solve starts cold every time.
    const Traction t = evaluate(soil, wheel, 1.0 + (i % 200), (i % 100) / 100.0, o);
    benchmark::DoNotOptimize(t);
    ++i;
  }
}
BENCHMARK(BM_WongReeceSimpson)->Unit(benchmark::kMicrosecond);

void BM_WongReeceRiemann500(benchmark::State& state) {
  const Soil soil = tyii();
  const Wheel wheel{0.075, 0.07, 0, 0.0};
  ModelOptions o;
  o.integration = Integration::riemann;
  o.riemann_points = 500;
  int i = 0;
  for (auto _ : state) {
    const Traction t = evaluate(soil, wheel, 1.0 + (i % 200), (i % 100) / 100.0, o);
    benchmark::DoNotOptimize(t);
    ++i;
  }
}
BENCHMARK(BM_WongReeceRiemann500)->Unit(benchmark::kMicrosecond);

// RFT (issue 43, item 2): one evaluation at a given load, sinkage solve
// included, <= 1 ms with about 2,000 surface elements. Arguments: grouser
// count (0: smooth, 1,800 elements; 12: 2,760), pile-up on or off, and
// whether the motion is new each call (1: cold, every element's stress
// computed, as at a study's first pass) or one of 133 met before (0: as a
// fit's later passes meet it, from the thread's cache of stresses, rft.cpp).
// Loads 10..40 N, travel slips -0.9..0.9 and slip angles 0..90 deg vary.
void BM_RftEvaluate(benchmark::State& state) {
  Soil soil;
  soil.rft_scale = 2.0e6;
  Wheel wheel{0.0625, 0.06, static_cast<int>(state.range(0)), 0.005};
  wheel.grouser_thickness = 0.002;
  ModelOptions o;
  o.kind = ModelKind::rft;
  o.slip_definition = SlipDefinition::travel;
  o.extensions.rft_pileup = state.range(1) != 0 ? 0.5 : 0.0;
  state.counters["elements"] = static_cast<double>(rft_wheel_mesh(wheel).size());
  int i = 0;
  for (auto _ : state) {
    const double jitter = state.range(2) != 0 ? 1e-7 * (i % 1000003) : 0.0;  // a new motion each call
    const double slip = -0.9 + 0.1 * (i % 19) + jitter, beta = (i % 7) * 15.0 * M_PI / 180.0;
    const SlipAngleTraction t = evaluate_slip_angle(soil, wheel, 10.0 + (i % 31), slip, beta, o);
    benchmark::DoNotOptimize(t);
    ++i;
  }
}
BENCHMARK(BM_RftEvaluate)
    ->ArgsProduct({{0, 12}, {0, 1}, {1, 0}})
    ->ArgNames({"grousers", "pileup", "cold"})
    ->Unit(benchmark::kMicrosecond);

void BM_TractionGrid100x100(benchmark::State& state) {
  const Soil soil = tyii();
  const Wheel wheel{0.075, 0.07, 0, 0.0};
  ModelOptions o;
  for (auto _ : state) {
    double sum = 0.0;
    for (int a = 0; a < 100; ++a) {
      for (int b = 0; b < 100; ++b) {
        sum += evaluate(soil, wheel, 0.1 + 199.9 * a / 99.0, b / 99.0, o).drawbar_pull;
      }
    }
    benchmark::DoNotOptimize(sum);
  }
}
BENCHMARK(BM_TractionGrid100x100)->Unit(benchmark::kMillisecond);

void BM_PolynomialSurfaceEvaluation(benchmark::State& state) {
  std::vector<double> c(PolynomialSurface::term_count(4), 0.1);
  const PolynomialSurface p(4, c);
  int i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(p(1.0 + (i % 200), (i % 100) / 100.0));
    ++i;
  }
}
BENCHMARK(BM_PolynomialSurfaceEvaluation)->Unit(benchmark::kNanosecond);

// The bundled Ding 2011 rows repeated to `rows` (loads 60..100 N, 3 % noise).
std::vector<WheelTestPoint> testbed_rows(std::size_t rows) {
  return roverlab::test::resampled_wheel_test(
      roverlab::io::read_wheel_test_csv(ROVERLAB_SOURCE_DIR "/tests/data/single_wheel/ding2011_tyii.csv"), rows);
}

void BM_SingleWheelStudy(benchmark::State& state) {
  const auto points = testbed_rows(static_cast<std::size_t>(state.range(0)));
  for (auto _ : state) {
    const auto report = roverlab::analysis::study_single_wheel(tyii(), points, {});
    benchmark::DoNotOptimize(report);
  }
  state.SetComplexityN(state.range(0));
}
BENCHMARK(BM_SingleWheelStudy)->Arg(12)->Arg(500)->Arg(5000)->Unit(benchmark::kSecond)->Iterations(1)->Complexity();

}  // namespace

BENCHMARK_MAIN();
