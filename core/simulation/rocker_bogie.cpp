#include "core/simulation/rocker_bogie.h"

#include <cmath>

#include "core/common/error.h"
#include "core/simulation/rocker_bogie_simulator.h"

namespace roverlab::simulation {

void set_effect(RockerBogieEffects& e, const std::string& name, double v) {
  if (!std::isfinite(v)) throw DataError("effect " + name + ": not a number");
  if (name == "soil-strength") {
    if (!(v > 0.1 && v < 10)) throw DataError("effect soil-strength must be 0.1..10");
    e.soil_strength = v;
  } else if (name == "slip-sinkage") {
    if (!(v >= 0 && v <= 2)) throw DataError("effect slip-sinkage must be 0..2");
    e.slip_sinkage_n1 = v;
  } else if (name == "grousers") {
    if (!(v >= 0 && v <= 0.05)) throw DataError("effect grousers (height, m) must be 0..0.05");
    e.grouser_height = v;
  } else if (name == "wheel-radius-scale") {
    if (!(v > 0.5 && v < 2)) throw DataError("effect wheel-radius-scale must be 0.5..2");
    e.wheel_radius_scale = v;
  } else if (name == "effect-start-x") {
    if (!(std::abs(v) <= 1000)) throw DataError("effect effect-start-x (m) must be -1000..1000");
    e.effect_start_x = v;
  } else if (name == "gyro-bias") {
    if (!(std::abs(v) <= 1)) throw DataError("effect gyro-bias (rad/s) must be -1..1");
    e.gyro_bias = v;
  } else if (name == "accel-bias") {
    if (!(std::abs(v) <= 10)) throw DataError("effect accel-bias (m/s^2) must be -10..10");
    e.accel_bias = v;
  } else if (name == "force-offset") {
    if (!(std::abs(v) <= 1000)) throw DataError("effect force-offset (N) must be -1000..1000");
    e.force_offset = v;
  } else if (name == "force-scale") {
    if (!(v > 0.1 && v < 10)) throw DataError("effect force-scale must be 0.1..10");
    e.force_scale = v;
  } else if (name == "encoder-dropout") {
    if (!(v >= 0 && v <= 100000)) throw DataError("effect encoder-dropout (start time, s) must be 0..100000");
    e.encoder_dropout_start = v;
  } else if (name == "imu-time-offset") {
    if (!(std::abs(v) <= 1)) throw DataError("effect imu-time-offset (s) must be -1..1");
    e.imu_time_offset = v;
  } else {
    throw DataError(
        "unknown effect '" + name +
        "' (soil-strength, slip-sinkage, grousers, wheel-radius-scale, "
        "effect-start-x, gyro-bias, accel-bias, force-offset, force-scale, encoder-dropout, imu-time-offset)");
  }
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
