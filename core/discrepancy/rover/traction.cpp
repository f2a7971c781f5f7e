// The rover discrepancy study's traction check (no simulation of the run):
// the net-traction estimates from the rover's own sensors (seed 003 chapter
// 5, Estimators 1 and 2 or 3) at near-steady-state points against the
// scenario's traction model at the same load and slip. A physical cause
// (soil, sinkage, grousers) moves the estimated traction off the model's
// surfaces; a sensor cause leaves it on them (or moves the loads with it).
#include <cmath>
#include <exception>

#include "core/discrepancy/rover/study.h"
#include "core/estimation/net_traction/net_traction.h"
#include "core/estimation/net_traction/surface.h"
#include "core/simulation/rocker_bogie_dynamics.h"

namespace roverlab::analysis::rover {

namespace {

struct Difference {
  double estimated = 0, model = 0, sigma = 0, load = 0;  // load: the points' mean normal load
};

// Mean of the estimates and of the model at the points, the standard error of
// their difference, and the points' mean load.
Difference compare(const std::vector<TractionPoint>& points, const simulation::rocker_bogie::TractionModel& model,
                   bool torque) {
  Difference d;
  double sum_e = 0, sum_m = 0, sum_d2 = 0, sum_w = 0;
  std::vector<double> diff;
  std::size_t unsupported = 0;
  for (const auto& p : points) {
    const auto t = model.evaluate(p.load, p.slip, false, unsupported);
    const double m = torque ? t.resistive_torque : t.drawbar_pull;
    const double e = torque ? p.resistive_torque : p.drawbar_pull;
    sum_e += e;
    sum_m += m;
    diff.push_back(e - m);
    sum_w += p.load;
  }
  const auto n = static_cast<double>(points.size());
  d.estimated = sum_e / n;
  d.model = sum_m / n;
  const double mean = d.estimated - d.model;
  for (double x : diff) sum_d2 += (x - mean) * (x - mean);
  d.sigma = std::sqrt(sum_d2 / (n - 1) / n);
  d.load = sum_w / n;
  return d;
}

// Consistent within 3 standard errors or `tolerance`, the net-traction
// estimator's own accuracy (its bias on runs with no effect).
RoverRedundancyCheck traction_check(const char* name, const char* unit, const Difference& d, double tolerance) {
  RoverRedundancyCheck c{name, d.estimated, d.model, std::max(d.sigma, tolerance / 3), unit, "", true};
  c.consistent = std::abs(d.estimated - d.model) <= 3 * c.sigma;
  c.verdict = c.consistent ? "the traction the rover's sensors show is the model's"
                           : "the rover's traction departs from the model's surfaces at the same load and slip: a "
                             "physical cause (soil, sinkage, grousers, wheel)";
  return c;
}

}  // namespace

std::vector<RoverRedundancyCheck> traction_checks(const log::Log& lg, const RoverScenarioModel& model) {
  estimation::net_traction::RoverConstants rover;
  rover.geometry = model.geometry;
  rover.parameters = model.parameters;
  estimation::NetTractionOptions options;
  options.compare_single_axis = false;
  try {
    const estimation::NetTractionResult r = estimation::run_net_traction(lg, rover, options);
    const NetTractionModel nm = rebuild_net_traction_model(lg, r, r.wheel_forces(), SteadyStateOptions{}, 2);
    const simulation::rocker_bogie::TractionModel traction(model.geometry, model.run,
                                                           true);  // the scenario's own effects are its model
    const Difference dp = compare(nm.estimated_points, traction, false);
    const Difference tau = compare(nm.estimated_points, traction, true);
    // Tolerances: 1 % of the mean wheel load for the drawbar pull (the estimator's
    // bias with no effect is about 0.1 N at 49 N), 5 % of the torque.
    return {traction_check("net-traction drawbar pull (mean of the steady points) vs the scenario's traction model",
                           "N", dp, 0.01 * dp.load),
            traction_check("net-traction resistive torque (mean of the steady points) vs the scenario's traction model",
                           "N*m", tau, 0.05 * std::abs(tau.model))};
  } catch (const std::exception& e) {
    RoverRedundancyCheck c{"net-traction estimates vs the scenario's traction model",
                           NAN,
                           NAN,
                           NAN,
                           "",
                           std::string("not run: ") + e.what(),
                           true};
    return {c};
  }
}

}  // namespace roverlab::analysis::rover
