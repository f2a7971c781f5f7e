#include "importers/soil_file.h"

#include <cmath>

#include "importers/json_resource.h"
#include "importers/named_file.h"

namespace roverlab::io {

terramechanics::Soil load_soil(const std::string& path) {
  const JsonResource file = read_json_resource(path, "soil file");
  const JsonNode j = file.root();
  require_format(j, "roverlab-soil", "soil");
  if (j.has("version") && optional_number(j, "version", 1) != 1) {
    j.fail("version", "unsupported soil file version (this RoverLab reads version 1)");
  }
  // Units, when written, must be the ones the numbers are read in.
  for (const auto& [field, unit] : {std::pair{"kc_unit", "Pa/m^(n-1)"}, std::pair{"kphi_unit", "Pa/m^n"}}) {
    if (j.has(field) && optional_string(j, field, unit) != unit) {
      j.fail(field, std::string("unit must be \"") + unit + "\"");
    }
  }
  terramechanics::Soil s;
  s.name = optional_string(j, "name", "");
  s.source = optional_string(j, "source", "");
  s.n = required_number_in(j, "n", 0.05, 3.0);
  s.cohesion = required_number_in(j, "cohesion_Pa", 0.0, 1e6);
  s.friction_angle = required_number_in(j, "friction_angle_deg", 0.1, 60.0) * M_PI / 180.0;
  s.shear_modulus = required_number_in(j, "shear_modulus_m", 1e-5, 1.0);
  // k_y of the slip-angle model (Ishigami 2007); K_s when not given.
  s.lateral_shear_modulus =
      j.has("lateral_shear_modulus_m") ? required_number_in(j, "lateral_shear_modulus_m", 1e-5, 1.0) : 0.0;
  s.kc = required_number_in(j, "kc", -1e9, 1e9);
  s.kphi = required_number_in(j, "kphi", 0.0, 1e10);
  s.c1 = required_number_in(j, "c1", 0.0, 1.0);
  s.c2 = required_number_in(j, "c2", -1.0, 1.0);
  s.density = j.has("density_kg_m3") ? required_number_in(j, "density_kg_m3", 100.0, 5000.0) : 1500.0;
  // RFT material scale zeta (core/terramechanics/rft.h), optional.
  if (j.has("rft_scale_N_m3")) s.rft_scale = required_number_in(j, "rft_scale_N_m3", 1e4, 1e8);
  return s;
}

terramechanics::Soil find_soil(const std::string& name_or_file, const std::vector<std::filesystem::path>& folders) {
  return load_soil(find_named_file(name_or_file, folders, "soil"));
}

}  // namespace roverlab::io
