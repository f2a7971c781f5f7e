#pragma once
// Measured single-wheel test points (testbed data such as Ding et al. 2011).

#include <optional>
#include <string>
#include <vector>

#include "core/terramechanics/soil.h"

namespace roverlab::terramechanics {

// lateral_force: F_y of a wheel at a slip angle (slip_angle_model.h).
enum class Quantity { drawbar_pull, torque, sinkage, lateral_force };
inline constexpr Quantity kQuantities[] = {Quantity::drawbar_pull, Quantity::torque, Quantity::sinkage,
                                           Quantity::lateral_force};
const char* to_string(Quantity q);
const char* unit_of(Quantity q);

struct WheelTestPoint {
  Wheel wheel;
  std::string wheel_label;  // e.g. "smooth", "grousered"
  double load = 0.0;        // N
  double slip = 0.0;
  // beta, rad: positive when the wheel's velocity has a component along +y
  // (the axle direction); 0 when the file has no slip_angle_deg column.
  double slip_angle = 0.0;
  std::optional<double> drawbar_pull;  // N
  // F_y, the soil's force on the wheel along +y, N (negative when it resists
  // a positive slip angle).
  std::optional<double> lateral_force;
  std::optional<double> torque;   // N m (driving torque = resistive torque in steady state)
  std::optional<double> sinkage;  // m
  int source_line = 0;

  std::optional<double> measured(Quantity q) const {
    switch (q) {
      case Quantity::drawbar_pull:
        return drawbar_pull;
      case Quantity::torque:
        return torque;
      case Quantity::sinkage:
        return sinkage;
      case Quantity::lateral_force:
        return lateral_force;
    }
    return std::nullopt;
  }
};

// Standard deviation of a measurement of each quantity.
struct MeasurementSigma {
  double drawbar_pull = 0.5;   // N
  double torque = 0.2;         // N m
  double sinkage = 0.0005;     // m
  double lateral_force = 0.5;  // N
  double of(Quantity q) const {
    return q == Quantity::drawbar_pull    ? drawbar_pull
           : q == Quantity::torque        ? torque
           : q == Quantity::lateral_force ? lateral_force
                                          : sinkage;
  }
  double& at(Quantity q) {
    switch (q) {
      case Quantity::drawbar_pull:
        return drawbar_pull;
      case Quantity::torque:
        return torque;
      case Quantity::lateral_force:
        return lateral_force;
      case Quantity::sinkage:
        break;
    }
    return sinkage;
  }
};

}  // namespace roverlab::terramechanics
