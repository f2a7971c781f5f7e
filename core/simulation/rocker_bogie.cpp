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

WheelCentrePath rolling_path() {
  WheelCentrePath p;
  p.name = "rolling (seed 003 Eq. 4.51)";
  const double k = M_PI / 2;
  p.z = [k](double x) { return 0.12 * std::cos(k * x - 1.6) + 0.01 * x; };
  p.dz = [k](double x) { return -0.12 * k * std::sin(k * x - 1.6) + 0.01; };
  p.ddz = [k](double x) { return -0.12 * k * k * std::cos(k * x - 1.6); };
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
