#pragma once
// Soil and wheel descriptions (data: resources/soils/*.json). SI units:
// stresses in Pa, lengths in m, angles in rad.

#include <cmath>
#include <string>

namespace roverlab::terramechanics {

struct Soil {
  std::string name;
  std::string source;           // citation of the values
  double n = 1.0;               // sinkage exponent n_s
  double cohesion = 0.0;        // c, Pa
  double friction_angle = 0.0;  // phi_s, rad
  double shear_modulus = 0.01;  // K_s, shear deformation parameter, m (k_x of Ishigami 2007)
  // k_y, lateral shear deformation modulus (slip-angle model), m; 0: K_s.
  double lateral_shear_modulus = 0.0;
  double kc = 0.0;    // modulus of cohesion, Pa / m^(n-1)
  double kphi = 0.0;  // modulus of friction, Pa / m^n
  double c1 = 0.18;   // maximum-stress angle coefficients (Eq. 2.10)
  double c2 = 0.32;
  double density = 1500.0;  // bulk density, kg/m^3 (bulldozing only)
  // zeta, RFT's material scale (Li et al. 2013): stress per unit depth of a
  // horizontal plate pushed straight down, N/m^3 (1e6 = 1 N/cm^3). The RFT
  // family fits it; this is its start.
  double rft_scale = 1.0e6;
};

// Eq. 2.12-2.13, seed 003: Wong's pressure-sinkage constants for a wheel width.
inline double k1(const Soil& s, double width) { return s.kc * std::pow(width, s.n - 1.0); }
inline double k2(const Soil& s, double width) { return s.kphi * std::pow(width, s.n - 1.0); }

struct Wheel {
  double radius = 0.075;  // m
  double width = 0.07;    // m
  int grouser_count = 0;
  double grouser_height = 0.0;     // m
  double grouser_thickness = 0.0;  // m (the RFT mesh; 0: thin plates)
};

}  // namespace roverlab::terramechanics
