#pragma once
// A rigid wheel at a slip angle (Ishigami, Miwa, Nagatani, Yoshida 2007,
// "Terramechanics-based model for steering maneuver of planetary exploration
// rovers on loose soil", J. Field Robotics 24(3):233-250), with the sidewall
// bulldozing term the paper takes from Hegedus. The longitudinal part is the
// Wong-Reece model of model.h: at slip angle 0 the two give the same values.
//
// Conventions: the slip angle beta is positive when the wheel's velocity has
// a component along +y (the axle direction); lateral_force is the soil's force
// on the wheel along +y, so it is negative when it resists a positive beta.

#include "core/terramechanics/model.h"

namespace roverlab::terramechanics {

// How the longitudinal and lateral shear stresses share the soil's strength.
enum class LateralShear {
  // Eq. 5 and 7 as printed: tau_x and tau_y each reach c + sigma tan(phi)
  // on their own, so drawbar pull and sinkage do not depend on beta.
  independent,
  // One Mohr-Coulomb strength for the resultant: tau = (c + sigma tan(phi))
  // (1 - exp(-J)), J = |(j_x / k_x, j_y / k_y)|, split along that vector.
  // Identical to Eq. 5 at beta = 0; drawbar pull falls as beta grows.
  shared,
};

struct LateralOptions {
  LateralShear shear = LateralShear::shared;
  // Scale on the sidewall bulldozing term of Eq. 10 (0 switches it off).
  double sidewall_scale = 1.0;
};

struct SlipAngleTraction : Traction {
  double slip_angle = 0.0;     // beta, rad
  double lateral_force = 0.0;  // F_y on the wheel along +y, N
  double lateral_shear = 0.0;  // the shear part of F_y (r b int tau_y), N, same sign as F_y
  double sidewall = 0.0;       // the sidewall bulldozing part of F_y, N, same sign as F_y
};

// Traction at normal load W (N), slip s in [-1, 1] and slip angle beta in
// [-pi/2, pi/2] rad, with the Wong-Reece options (kind wong_reece or
// ishigami; extensions as in model.h) and the lateral options. With a hint
// (model.h), the sinkage solves start from it and update it.
SlipAngleTraction evaluate_slip_angle(const Soil& soil, const Wheel& wheel, double load, double slip, double slip_angle,
                                      const ModelOptions& options = {}, const LateralOptions& lateral = {},
                                      EntryAngleHint* hint = nullptr);

// k_y: the soil's lateral shear-deformation modulus, K_s when not given.
double lateral_shear_modulus(const Soil& soil);

// The Hegedus sidewall bulldozing resistance per unit length of the sidewall
// at depth h (N/m), as Ishigami 2007 Eq. 10 uses it; exposed for tests.
double sidewall_resistance(const Soil& soil, double soil_strength, double depth);

}  // namespace roverlab::terramechanics
