#pragma once
// Rigid wheel on deformable soil: Bekker (seed 003 Eq. 2.1-2.7) and
// Wong-Reece (Eq. 2.8-2.22) with the skid extension (Eq. 2.26-2.27) and
// switchable extensions from the literature.

#include <string>

#include "core/terramechanics/soil.h"

namespace roverlab::terramechanics {

// ishigami: Wong-Reece with a slip angle and the lateral force
// (slip_angle_model.h); evaluate() gives its values at slip angle 0.
// rft: granular resistive force theory on the wheel's surface mesh (rft.h),
// at any slip angle; evaluate() gives its values at slip angle 0.
enum class ModelKind { bekker, wong_reece, ishigami, rft };
// The families that give a lateral force (evaluate_slip_angle).
inline bool has_lateral_force(ModelKind k) { return k == ModelKind::ishigami || k == ModelKind::rft; }
enum class Integration { simpson, riemann };

// Extensions of the baseline model. Each is off at its neutral value.
struct Extensions {
  // Slip-sinkage (Ding et al. 2011, J. Terramechanics 48(1)): the sinkage
  // exponent grows with slip, n = n0 + n1 * |s|.
  double slip_sinkage_n1 = 0.0;
  // Grousers (Ding et al. 2011, "equivalent radius"): soil shears at
  // r + lambda * h, lambda in [0, 1]; only for wheels with grousers.
  bool grousers = false;
  double grouser_effectiveness = 1.0;
  // Bulldozing resistance of the soil pushed ahead of the wheel (Bekker
  // 1960, in Wong, Theory of Ground Vehicles, Eq. 2.79), scaled.
  bool bulldozing = false;
  double bulldozing_scale = 1.0;
  // Soil strength factor: multiplies c, tan(phi), kc and kphi (a uniformly
  // weaker or stronger soil than the nominal description).
  double soil_strength = 1.0;
  // Slip-dependent shear deformation modulus (Ding et al. 2015, "Interaction
  // mechanics model for rigid driving wheels of planetary rovers moving on
  // sandy terrain with consideration of multiple physical effects", J. Field
  // Robotics 32, p. 827, doi:10.1002/rob.21533): their K linear in slip,
  // written K = K_0 (1 + k_s s), s >= 0 (the skid side mirrors it; the form
  // from memory, not checked against the paper).
  double shear_modulus_slip = 0.0;
  // Rear angle (Wong & Reece 1967; Ishigami et al. 2007): the soil rebounds
  // and the contact reaches theta_r = -kappa theta_0 behind the bottom.
  double rear_angle_ratio = 0.0;
  // Peaked ("hump") shear stress-shear displacement relation of dense sand
  // and compact soils (Wong, Theory of Ground Vehicles, ch. 2; form from
  // memory, see docs/terramechanics.md): replaces 1 - exp(-j/K) by
  //   K_r [1 + (1 / (K_r (1 - 1/e)) - 1) exp(1 - j/K_w)] (1 - exp(-j/K_w)),
  // equal to 1 at j = K_w and tending to K_r; K_r in (0, 1] the residual to
  // maximum shear stress ratio, K_w (m) the displacement of the maximum (it
  // takes the place of K_s; slip-shear-modulus scales it alike).
  bool shear_peak = false;
  double shear_residual_ratio = 0.7;
  double shear_peak_displacement = 0.02;
  // Slip-angle model only: a scale on the Hegedus sidewall term (Ishigami
  // et al. 2007 Eq. 10), multiplying LateralOptions::sidewall_scale.
  double sidewall_scale = 1.0;
  // RFT only (rft.h). Pile-up: the free surface ahead of a face that pushes
  // sand horizontally is raised by this fraction of the sinkage (times the
  // cosine between the face's normal and the horizontal motion); 0: flat.
  double rft_pileup = 0.0;
  // Depth-dependent material scale zeta (1 + k d / r), d the depth; 0: Li 2013's linear depth.
  double rft_depth_scale = 0.0;
};

// How a measured slip is read when the wheel is at a slip angle beta (the
// slip-angle model only; at beta = 0 the two agree).
enum class SlipDefinition {
  // Ishigami et al. 2007: s = 1 - v_x / (r w), v_x the velocity along the
  // wheel's heading; a wheel sliding sideways at beta = 90 deg has s = 1.
  longitudinal,
  // s = 1 - |v| / (r w), v the wheel's travel velocity (a testbed carriage's
  // speed); then v_x = (1 - s) r w cos(beta), v_y = (1 - s) r w sin(beta).
  travel,
};
const char* to_string(SlipDefinition d);
SlipDefinition parse_slip_definition(const std::string& text);  // throws DataError

struct ModelOptions {
  ModelKind kind = ModelKind::wong_reece;
  SlipDefinition slip_definition = SlipDefinition::longitudinal;
  Integration integration = Integration::simpson;
  int riemann_points = 500;
  Extensions extensions;
};

enum class TractionStatus {
  ok,
  unsupported_load,  // no entry angle below pi/2 carries the load
  invalid_input,     // non-finite or non-positive load, slip outside [-1, 1]
};

// Where the last evaluation of one point found its entry angles (the
// slip's and, for a skidding wheel, zero slip's): a fit evaluates each point
// again and again at nearby parameters, and the next sinkage solve starts
// there (2-3 integrals instead of about 7). The root meets the same
// tolerance as from a cold start; a solve that does not converge from the
// hint in 4 steps starts cold. Used by the fits (soil_identification.cpp).
struct EntryAngleHint {
  double entry = 0.0, zero_slip_entry = 0.0;  // 0: none yet
};

struct Traction {
  TractionStatus status = TractionStatus::invalid_input;
  double entry_angle = 0.0;       // theta_0, rad
  double max_stress_angle = 0.0;  // theta_m, rad (Wong-Reece)
  double drawbar_pull = 0.0;      // N
  double resistive_torque = 0.0;  // N m
  double sinkage = 0.0;           // r (1 - cos theta_0), m
  // The compaction (and bulldozing) resistance inside drawbar_pull, N >= 0:
  // drawbar_pull = thrust - motion_resistance. The thrust follows the rim's
  // motion over the soil, the resistance opposes the centre's motion.
  double motion_resistance = 0.0;
  bool ok() const { return status == TractionStatus::ok; }
};

// Traction of one wheel at normal load W (N) and slip s in [-1, 1]
// (negative: skid, by the anti-symmetric extension Eq. 2.26-2.27).
Traction evaluate(const Soil& soil, const Wheel& wheel, double load, double slip, const ModelOptions& options = {});

// Slip or skid and the direction of the traction forces from the wheel
// centre speed v (m/s) and the wheel rate omega (rad/s): Eq. 2.23 with the
// cases of Table 2.3.
struct SlipState {
  double slip = 0.0;
  double direction = 1.0;
  int table_case = 1;  // row of Table 2.3
};
SlipState slip_state(double v, double omega, double radius);

const char* to_string(TractionStatus status);
ModelKind parse_model_kind(const std::string& text);     // throws DataError
Integration parse_integration(const std::string& text);  // throws DataError

}  // namespace roverlab::terramechanics
