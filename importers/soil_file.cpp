#include "importers/soil_file.h"

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>

#include "core/common/error.h"
#include "importers/named_file.h"

namespace roverlab::io {

using nlohmann::json;

namespace {

double number(const json& j, const char* key, double lo, double hi, const std::string& path) {
  if (!j.contains(key) || !j.at(key).is_number()) {
    throw InputError(path, std::string("soil parameter '") + key + "' must be a number");
  }
  const double v = j.at(key).get<double>();
  if (!std::isfinite(v) || v < lo || v > hi) {
    throw InputError(path, std::string("soil parameter '") + key + "' = " + std::to_string(v) +
                               " is outside [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
  }
  return v;
}

}  // namespace

terramechanics::Soil load_soil(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path, "cannot open soil file");
  json j;
  try {
    j = json::parse(in);
  } catch (const json::parse_error& e) {
    throw InputError(path, std::string("soil file is not valid JSON: ") + e.what());
  }
  if (!j.is_object() || j.value("format", std::string()) != "roverlab-soil") {
    throw InputError(path, "not a RoverLab soil ('format' must be \"roverlab-soil\")");
  }
  terramechanics::Soil s;
  s.name = j.value("name", std::string());
  s.source = j.value("source", std::string());
  s.n = number(j, "n", 0.05, 3.0, path);
  s.cohesion = number(j, "cohesion_Pa", 0.0, 1e6, path);
  s.friction_angle = number(j, "friction_angle_deg", 0.1, 60.0, path) * M_PI / 180.0;
  s.shear_modulus = number(j, "shear_modulus_m", 1e-5, 1.0, path);
  s.kc = number(j, "kc", -1e9, 1e9, path);
  s.kphi = number(j, "kphi", 0.0, 1e10, path);
  s.c1 = number(j, "c1", 0.0, 1.0, path);
  s.c2 = number(j, "c2", -1.0, 1.0, path);
  s.density = j.contains("density_kg_m3") ? number(j, "density_kg_m3", 100.0, 5000.0, path) : 1500.0;
  return s;
}

terramechanics::Soil find_soil(const std::string& name_or_file,
                               const std::vector<std::filesystem::path>& folders) {
  return load_soil(find_named_file(name_or_file, folders, "soil"));
}

}  // namespace roverlab::io
