#pragma once
// Soils of seed 003 (Table 2.2, Appendix A.2, A.3), read from
// resources/soils/*.json through the soil reader, and the Kapvik wheel
// (Table 2.1).

#include <map>
#include <string>

#include "core/terramechanics/soil.h"
#include "importers/soil_file.h"

namespace roverlab::test {

// resources/soils/NAME.json, read once per test program.
inline const terramechanics::Soil& resource_soil(const std::string& name) {
  static const auto folder = std::string(ROVERLAB_RESOURCES_DIR) + "/soils";
  static std::map<std::string, terramechanics::Soil> soils;
  auto it = soils.find(name);
  if (it == soils.end()) it = soils.emplace(name, io::find_soil(name, {folder})).first;
  return it->second;
}

inline terramechanics::Soil ding_tyii() { return resource_soil("ding_tyii"); }
inline terramechanics::Soil lunar_nominal() { return resource_soil("lunar_nominal"); }
inline terramechanics::Soil dry_sand() { return resource_soil("dry_sand"); }

inline terramechanics::Wheel kapvik_wheel() { return {0.075, 0.07, 0, 0.0}; }

}  // namespace roverlab::test
