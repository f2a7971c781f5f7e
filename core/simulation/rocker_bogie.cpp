#include "core/simulation/rocker_bogie.h"

#include <cmath>
#include <cstdio>

#include "core/common/error.h"
#include "core/simulation/effects.h"
#include "core/simulation/rocker_bogie_simulator.h"

namespace roverlab::simulation {

void set_effect(RockerBogieEffects& e, const std::string& name, double v) {
  const EffectSpec* spec = find_effect(name);
  if (spec == nullptr) throw DataError("unknown effect '" + name + "' (" + effect_names() + ")");
  if (!std::isfinite(v)) throw DataError("effect " + name + ": not a number");
  if (!(v >= spec->lower && v <= spec->upper)) {
    char range[64];
    std::snprintf(range, sizeof range, "%g..%g", spec->lower, spec->upper);
    throw DataError("effect " + name + " (" + spec->what +
                    (std::string(spec->unit) == "1" ? "" : ", " + std::string(spec->unit)) + ") must be " + range);
  }
  e.*(spec->member) = v;
}

WheelCentrePath rolling_path(double amplitude) {
  WheelCentrePath p;
  p.name = amplitude == 0.12 ? "rolling (seed 003 Eq. 4.51)"
                             : "rolling (seed 003 Eq. 4.51, hills of amplitude " + std::to_string(amplitude) + " m)";
  const double k = M_PI / 2;
  const double a = amplitude;
  p.z = [k, a](double x) { return a * std::cos(k * x - 1.6) + 0.01 * x; };
  p.dz = [k, a](double x) { return -a * k * std::sin(k * x - 1.6) + 0.01; };
  p.ddz = [k, a](double x) { return -a * k * k * std::cos(k * x - 1.6); };
  return p;
}

WheelCentrePath slope_path(double degrees) {
  WheelCentrePath p;
  p.name = "slope " + std::to_string(degrees) + " deg";
  const double k = std::tan(degrees * M_PI / 180.0);
  p.z = [k](double x) { return k * x; };
  p.dz = [k](double) { return k; };
  p.ddz = [](double) { return 0.0; };
  return p;
}

WheelCentrePath bump_path(double height, double x0, double length) {
  WheelCentrePath p;
  p.name = "bump " + std::to_string(height) + " m at x = " + std::to_string(x0) + " m";
  const double w = 2.0 * M_PI / length;
  auto inside = [x0, length](double x) { return x >= x0 && x <= x0 + length; };
  p.z = [=](double x) { return inside(x) ? 0.5 * height * (1.0 - std::cos(w * (x - x0))) : 0.0; };
  p.dz = [=](double x) { return inside(x) ? 0.5 * height * w * std::sin(w * (x - x0)) : 0.0; };
  p.ddz = [=](double x) { return inside(x) ? 0.5 * height * w * w * std::cos(w * (x - x0)) : 0.0; };
  return p;
}

WheelCentrePath flat_path(double h) {
  WheelCentrePath p;
  p.name = "flat";
  p.z = [h](double) { return h; };
  p.dz = [](double) { return 0.0; };
  p.ddz = [](double) { return 0.0; };
  return p;
}

RockerBogieResult simulate_rocker_bogie(const PlanarRockerBogieGeometry& g, const RockerBogieParameters& p,
                                        const RockerBogieRun& run) {
  return RockerBogieSimulator(g, p, run).run();
}

}  // namespace roverlab::simulation

namespace roverlab::simulation {

std::string stuck_note(const log::Log& simulated, double desired_speed, double duration) {
  const log::Stream* pose = simulated.find_stream("truth/pose");
  const log::Stream* wheels = simulated.find_stream("truth/wheels");
  const double asked = desired_speed * duration;
  if (pose == nullptr || pose->size() < 2 || !(asked > 0)) return {};
  const auto& x = pose->channel("x").values;
  const double driven = x.back() - x.front();
  if (driven >= 0.25 * asked) return {};
  double slip = 0;
  std::size_t n = 0;
  for (int k = 1; wheels != nullptr && k <= 3; ++k) {
    const log::Channel* c = wheels->find_channel("slip_" + std::to_string(k));
    if (c == nullptr) continue;
    for (double v : c->values) {
      if (std::isfinite(v)) slip += v, ++n;
    }
  }
  char buf[320];
  std::snprintf(buf, sizeof buf,
                "the rover drove %.2f m of the %.2f m its %.3g m/s speed command asks for (mean wheel slip %.2f): "
                "the soil does not carry it over this path, and the log describes a stuck rover",
                driven, asked, desired_speed, n > 0 ? slip / static_cast<double>(n) : NAN);
  return buf;
}

}  // namespace roverlab::simulation
