// The rover discrepancy study's checks that need no simulation: the sensors
// against each other and against the static balance of the scenario's masses.
#include <cmath>

#include "core/analysis/rover_discrepancy.h"
#include "core/analysis/rover_prediction.h"

namespace roverlab::analysis::rover {

namespace {

double mean_of(const std::vector<double>& v, std::size_t from, std::size_t to) {
  double s = 0;
  for (std::size_t k = from; k < to; ++k) s += v[k];
  return s / static_cast<double>(to - from);
}

RoverRedundancyCheck check(std::string name, double value, double expected, double sigma, std::string unit,
                           const char* agree, const char* disagree) {
  RoverRedundancyCheck c{std::move(name), value, expected, sigma, std::move(unit), "", true};
  c.consistent = std::abs(value - expected) <= 3 * sigma;
  c.verdict = c.consistent ? agree : disagree;
  return c;
}

}  // namespace

std::vector<RoverRedundancyCheck> redundancy_checks(const std::vector<MeasuredChannel>& ch,
                                                    const RoverScenarioModel& model) {
  std::vector<RoverRedundancyCheck> out;
  const auto& fx = ch[5].values;
  const auto& fz = ch[6].values;
  const std::size_t n = fx.size();
  const double g = model.parameters.gravity;
  // Pitch from the accelerometers (specific force in rover axes, quasi-static), theta = atan2(-f_x, f_z).
  std::vector<double> pitch(n);
  for (std::size_t k = 0; k < n; ++k) pitch[k] = std::atan2(-fx[k], fz[k]);
  const double T = ch[5].time.back() - ch[5].time.front();
  const std::size_t m = std::min<std::size_t>(n / 4, 100);
  const double dtheta = mean_of(pitch, n - m, n) - mean_of(pitch, 0, m);
  const double gyro = mean_of(ch[4].values, 0, ch[4].values.size());
  const double sigma = ch[4].sigma / std::sqrt(static_cast<double>(ch[4].values.size())) +
                       std::sqrt(2.0 / static_cast<double>(m)) * ch[5].sigma / g / T;
  out.push_back(check("pitch rate (mean) vs the accelerometers' pitch change over the run", gyro, dtheta / T, sigma,
                      "rad/s", "the gyro integrates to the pitch the accelerometers see",
                      "the gyro disagrees with the accelerometers' pitch: a gyro bias, or accelerations the "
                      "quasi-static pitch misses"));
  // The soil's forces on the wheels in the world (link axes rotated by pitch, plus the bogie for wheels 2 and 3).
  const auto& p = model.parameters;
  const double mass = p.body_mass + p.bogie_mass + 3 * p.wheel_mass;
  const std::size_t nf = std::min(ch[8].values.size(), n);
  double vertical = 0, horizontal = 0;
  for (std::size_t k = 0; k < nf; ++k) {
    for (std::size_t i = 0; i < 3; ++i) {
      const double a = pitch[k] + (i == 0 ? 0.0 : ch[0].values[std::min(k, ch[0].values.size() - 1)]);
      const double load = ch[8 + i].values[k], perp = ch[11 + i].values[k];
      vertical += load * std::cos(a) - perp * std::sin(a);
      horizontal += load * std::sin(a) + perp * std::cos(a);
    }
  }
  vertical /= static_cast<double>(nf);
  horizontal /= static_cast<double>(nf);
  // Stated tolerance: 0.5 % of the weight (the quasi-static balance and the accelerometers' pitch).
  const double tol = 0.005 * mass * g / 3;
  out.push_back(check("wheel forces, vertical sum (mean) vs the weight of the side", vertical, mass * g, tol, "N",
                      "the force sensors carry the rover's weight",
                      "the force sensors do not add up to the weight: a force scale or offset"));
  out.push_back(check("wheel forces, horizontal sum (mean) vs zero at quasi-static speed", horizontal, 0.0, tol, "N",
                      "the drawbar pulls balance", "the horizontal forces do not balance: a force offset or bias"));
  return out;
}

}  // namespace roverlab::analysis::rover
