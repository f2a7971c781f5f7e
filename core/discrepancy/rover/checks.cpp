// The rover discrepancy study's checks that need no simulation: the sensors
// against each other and against the static balance of the scenario's masses.
#include <array>
#include <cmath>
#include <cstdio>

#include "core/discrepancy/rover/prediction.h"
#include "core/discrepancy/rover/study.h"

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

// Mean slip over the run from the velocimeter and the wheel encoders:
// 1 - (distance the body moved) / (nominal radius x mean wheel angle turned).
double body_distance(const std::vector<double>& time, const std::vector<double>& speed) {
  double distance = 0;
  for (std::size_t k = 1; k < time.size() && k < speed.size(); ++k) {
    distance += 0.5 * (speed[k] + speed[k - 1]) * (time[k] - time[k - 1]);
  }
  return distance;
}

double rolled_out(const std::array<const std::vector<double>*, 3>& wheel_angles, double radius) {
  double turned = 0;
  for (const auto* a : wheel_angles) turned += (a->back() - a->front()) / 3;
  return turned * radius;
}

double run_slip(const std::vector<double>& time, const std::vector<double>& speed,
                const std::array<const std::vector<double>*, 3>& wheel_angles, double radius) {
  const double rolled = rolled_out(wheel_angles, radius);
  return rolled > 0 ? 1 - body_distance(time, speed) / rolled : NAN;
}

}  // namespace

// The velocimeter against the wheel encoders times the nominal radius: the
// mean slip they give, against the same from the simulation's channels (a
// wheel radius or soil cause changes it; a sensor bias does not).
// `measured` is slip_regime()'s: the same integration over the measured channels.
RoverRedundancyCheck slip_check(const std::vector<MeasuredChannel>& ch, const RoverSlipRegime& regime,
                                const std::array<std::vector<double>, kChannels>& predicted, double radius) {
  const double measured = regime.mean_slip;
  const double model = run_slip(ch[7].time, predicted[7], {&predicted[1], &predicted[2], &predicted[3]}, radius);
  // Stated tolerance: 0.005 of slip (the velocimeter's noise integrates to far less).
  return check("velocimeter vs wheel encoders x nominal radius: mean slip over the run", measured, model, 0.005 / 3, "",
               "the body moves as far as the model's wheels and slip say",
               "the body moves another distance than the wheels and the model's slip say: wheel radius or soil");
}

RoverSlipRegime slip_regime(const std::vector<MeasuredChannel>& ch, double radius) {
  RoverSlipRegime r;
  r.distance = body_distance(ch[7].time, ch[7].values);
  r.rolled_out = rolled_out({&ch[1].values, &ch[2].values, &ch[3].values}, radius);
  r.mean_slip = r.rolled_out > 0 ? 1 - r.distance / r.rolled_out : NAN;
  const double s = r.mean_slip;
  r.stuck = !(s < 0.9);  // NaN (wheels that did not turn forwards) is not a rolling rover either
  const char* regime = !std::isfinite(s) ? "the wheels did not turn forwards"
                       : s >= 0.9        ? "stuck: the wheels spin and the rover barely moves"
                       : s >= 0.5        ? "high slip"
                       : s >= 0.2        ? "moderate slip"
                       : s >= -0.05      ? "low slip (rolling)"
                                         : "skidding (the body moves further than the wheels roll)";
  char buf[256];
  std::snprintf(buf, sizeof buf,
                "Slip regime: %s; the body moved %.3g m while the wheels rolled out %.3g m (mean slip %.2f, "
                "velocimeter against wheel encoders).",
                regime, r.distance, r.rolled_out, s);
  r.text = buf;
  return r;
}

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
