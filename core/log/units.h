#pragma once
// Unit strings and their conversion to SI. A log stores SI values (angles in
// radians); importers convert what a file declares with these rules.

#include <string>
#include <string_view>
#include <vector>

namespace roverlab::log {

struct UnitConversion {
  std::string si_unit;  // canonical SI unit string, e.g. "rad/s"
  double factor = 1.0;  // si_value = value * factor + offset
  double offset = 0.0;
};

// Conversion of `unit` to SI. Throws DataError naming the unit when unknown.
UnitConversion unit_to_si(std::string_view unit);

// True when `unit` is a unit string this registry knows.
bool is_known_unit(std::string_view unit);

// Every unit string the registry accepts (for error messages and docs).
std::vector<std::string> known_units();

}  // namespace roverlab::log
