#pragma once
// Soils of seed 003 (Table 2.2, Appendix A.2, A.3) and the Kapvik wheel
// (Table 2.1), written out for the core tests (the JSON files in
// resources/soils are read by the importer tests).

#include <cmath>

#include "core/terramechanics/soil.h"

namespace roverlab::test {

inline terramechanics::Soil ding_tyii() {
  terramechanics::Soil s;
  s.name = "ding_tyii";
  s.n = 1.1;
  s.cohesion = 250.0;
  s.friction_angle = 31.9 * M_PI / 180.0;
  s.shear_modulus = 0.0114;
  s.kc = 15.6e3;
  s.kphi = 2407.4e3;
  s.c1 = 0.18;
  s.c2 = 0.32;
  s.density = 1600.0;
  return s;
}

inline terramechanics::Soil lunar_nominal() {
  terramechanics::Soil s = ding_tyii();
  s.name = "lunar_nominal";
  s.n = 1.0;
  s.cohesion = 170.0;
  s.friction_angle = 35.0 * M_PI / 180.0;
  s.shear_modulus = 0.0178;
  s.kc = 1.4e3;
  s.kphi = 820e3;
  return s;
}

inline terramechanics::Soil dry_sand() {
  terramechanics::Soil s = ding_tyii();
  s.name = "dry_sand";
  s.n = 1.1;
  s.cohesion = 1040.0;
  s.friction_angle = 28.0 * M_PI / 180.0;
  s.shear_modulus = 0.0175;
  s.kc = 0.99e3;
  s.kphi = 1528.43e3;
  return s;
}

inline terramechanics::Wheel kapvik_wheel() { return {0.075, 0.07, 0, 0.0}; }

}  // namespace roverlab::test
