#pragma once
// Granular resistive force theory (RFT) for a rigid wheel in dry sand.
//
// Stress on a surface element below the free surface at depth d:
//   sigma = zeta d alpha^gen(beta, gamma)
// with Li, Zhang and Goldman's generic alpha_x, alpha_z Fourier fit (Science
// 339:1408, 2013), beta the element's angle and gamma the angle of its motion
// in the vertical plane of its velocity, zeta the medium's material scale.
// A wheel moving in 3D (any slip, slip angle up to 90 deg, braking) is the
// sum over its surface elements, each taken in the vertical plane of its own
// velocity (after Treers et al. 2021, IEEE RA-L 6(2), and Agarwal et al.
// 2019, J. Terramechanics 85 for wheels). Only leading elements (outward
// normal along the velocity) below the surface carry stress. RFT is rate
// independent: only directions of motion matter.
//
// Frames: wheel frame x along the heading, y along the axle (+y as in
// slip_angle_model.h), z up; the wheel turns forward about +y.

#include <vector>

#include "core/terramechanics/slip_angle_model.h"

namespace roverlab::terramechanics {

// Li et al. 2013's generic coefficients, alpha(0, pi/2) = (0, 1): per unit
// zeta. Returns (alpha_x, alpha_z) for the plate angle beta and the angle
// gamma of its motion below the horizontal (gamma = pi/2: straight down),
// alpha_x > 0 resisting motion along +x.
struct Alpha {
  double x, z;
};
Alpha generic_alpha(double beta, double gamma);

// One surface element of the wheel: centre (wheel frame, from the axle), unit
// outward normal, area, and the part it belongs to.
enum class RftPart { rim, side, grouser };
struct RftElement {
  double px, py, pz;
  double nx, ny, nz;
  double area;
  RftPart part;
};

// The mesh's resolution. The defaults give about 1,800 elements for a
// smooth wheel (rim 90 x 8, two side faces 90 x 6 each), over the lower
// half of the wheel (what a sinkage up to the radius can immerse).
struct RftResolution {
  int angles = 90;         // over the lower half, pi rad
  int across = 8;          // across the rim's width (and each grouser's)
  int rings = 6;           // radially on each side face
  int grouser_rows = 2;    // along a grouser's height, each face
  int grouser_phases = 4;  // grouser positions averaged over one pitch
};

// The wheel's surface: rim, both side faces and grousers (count, height
// times height_scale, thickness; front, back and tip faces; their small side
// ends left out), each grouser at grouser_phases positions spread evenly over
// one pitch with 1/grouser_phases of its area, so that the forces are those
// averaged over the wheel's turn.
std::vector<RftElement> rft_wheel_mesh(const Wheel& wheel, double grouser_height_scale = 1.0,
                                       const RftResolution& resolution = {});

// The soil's force on a surface element per unit material scale and unit
// depth (N / (N/m^3 m)), for the element's velocity u (wheel frame, any
// scale): zero for a trailing element (n . u <= 0).
struct Vec3 {
  double x, y, z;
};
Vec3 rft_element_stress(const RftElement& e, const Vec3& velocity);

// The wheel's velocity directions for a slip and slip angle read as
// options.slip_definition defines (model.h), with r w = 1: the centre's
// velocity and the rim speed r w, both scaled by cos(beta) (at least 1e-6) in
// the longitudinal reading; 90 deg is the limit from below.
struct WheelMotion {
  Vec3 centre;
  double rim_speed;
};
WheelMotion rft_wheel_motion(double slip, double slip_angle, SlipDefinition definition);

// RFT traction at load W (N), slip s in [-1, 1] and slip angle in [-pi/2,
// pi/2]: drawbar pull (F_x), lateral force (F_y; lateral_shear the rim's and
// grousers' part, sidewall the side faces' part), resistive torque, sinkage
// (depth of the rim's bottom below the free surface, from F_z = W) and its
// entry angle. Negative slip: 1 - v / (r w) < 0 read literally (the wheel
// turns slower than it travels). Extensions used: soil_strength (scales
// zeta), grousers with grouser_effectiveness (scales the grouser height),
// rft_pileup, rft_depth_scale.
SlipAngleTraction evaluate_rft(const Soil& soil, const Wheel& wheel, double load, double slip, double slip_angle,
                               const ModelOptions& options = {});

}  // namespace roverlab::terramechanics
