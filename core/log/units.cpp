#include "core/log/units.h"

#include <cmath>

#include "core/common/error.h"

namespace roverlab::log {
namespace {

struct UnitRow {
  const char* name;
  const char* si;
  double factor;
  double offset;
};

constexpr double kPi = 3.14159265358979323846;
constexpr double kStandardGravity = 9.80665;  // m/s^2, CGPM 1901

// Accepted spellings. Each row maps a unit string to its SI unit.
const UnitRow kUnits[] = {
    // dimensionless
    {"1", "1", 1.0, 0.0},
    {"-", "1", 1.0, 0.0},
    {"%", "1", 0.01, 0.0},
    {"count", "count", 1.0, 0.0},
    {"bool", "bool", 1.0, 0.0},
    // time, frequency
    {"s", "s", 1.0, 0.0},
    {"ms", "s", 1e-3, 0.0},
    {"us", "s", 1e-6, 0.0},
    {"ns", "s", 1e-9, 0.0},
    {"min", "s", 60.0, 0.0},
    {"h", "s", 3600.0, 0.0},
    {"Hz", "Hz", 1.0, 0.0},
    // length, area, volume
    {"m", "m", 1.0, 0.0},
    {"mm", "m", 1e-3, 0.0},
    {"cm", "m", 1e-2, 0.0},
    {"km", "m", 1e3, 0.0},
    {"m^2", "m^2", 1.0, 0.0},
    {"m^3", "m^3", 1.0, 0.0},
    // velocity
    {"m/s", "m/s", 1.0, 0.0},
    {"mm/s", "m/s", 1e-3, 0.0},
    {"cm/s", "m/s", 1e-2, 0.0},
    {"km/h", "m/s", 1.0 / 3.6, 0.0},
    // acceleration
    {"m/s^2", "m/s^2", 1.0, 0.0},
    {"m/s2", "m/s^2", 1.0, 0.0},
    {"m/s/s", "m/s^2", 1.0, 0.0},
    {"g_n", "m/s^2", kStandardGravity, 0.0},
    {"mg_n", "m/s^2", kStandardGravity * 1e-3, 0.0},
    // angle
    {"rad", "rad", 1.0, 0.0},
    {"mrad", "rad", 1e-3, 0.0},
    {"deg", "rad", kPi / 180.0, 0.0},
    {"rev", "rad", 2.0 * kPi, 0.0},
    // angular rate and acceleration
    {"rad/s", "rad/s", 1.0, 0.0},
    {"deg/s", "rad/s", kPi / 180.0, 0.0},
    {"deg/h", "rad/s", kPi / 180.0 / 3600.0, 0.0},
    {"rpm", "rad/s", 2.0 * kPi / 60.0, 0.0},
    {"rev/s", "rad/s", 2.0 * kPi, 0.0},
    {"rad/s^2", "rad/s^2", 1.0, 0.0},
    // mass, force, torque, pressure
    {"kg", "kg", 1.0, 0.0},
    {"g", "kg", 1e-3, 0.0},
    {"N", "N", 1.0, 0.0},
    {"mN", "N", 1e-3, 0.0},
    {"kN", "N", 1e3, 0.0},
    {"N*m", "N*m", 1.0, 0.0},
    {"N m", "N*m", 1.0, 0.0},
    {"Nm", "N*m", 1.0, 0.0},
    {"N.m", "N*m", 1.0, 0.0},
    {"Pa", "Pa", 1.0, 0.0},
    {"kPa", "Pa", 1e3, 0.0},
    {"MPa", "Pa", 1e6, 0.0},
    {"kg/m^3", "kg/m^3", 1.0, 0.0},
    // electrical, power, temperature
    {"V", "V", 1.0, 0.0},
    {"A", "A", 1.0, 0.0},
    {"mA", "A", 1e-3, 0.0},
    {"W", "W", 1.0, 0.0},
    {"K", "K", 1.0, 0.0},
    {"degC", "K", 1.0, 273.15},
};

}  // namespace

UnitConversion unit_to_si(std::string_view unit) {
  for (const auto& row : kUnits) {
    if (unit == row.name) return UnitConversion{row.si, row.factor, row.offset};
  }
  throw DataError("unknown unit '" + std::string(unit) + "' (see docs/log-format.md for the accepted unit strings)");
}

bool is_known_unit(std::string_view unit) {
  for (const auto& row : kUnits) {
    if (unit == row.name) return true;
  }
  return false;
}

std::vector<std::string> known_units() {
  std::vector<std::string> names;
  for (const auto& row : kUnits) names.emplace_back(row.name);
  return names;
}

}  // namespace roverlab::log
