#pragma once
// Soil identification: estimate a chosen subset of soil and extension
// parameters from measured wheel points with Ceres (bounds, robust loss,
// +-1 sigma from ceres::Covariance).

#include <string>
#include <vector>

#include "core/terramechanics/model.h"
#include "core/terramechanics/wheel_test.h"

namespace roverlab::terramechanics {

enum class Parameter {
  n,
  cohesion,
  friction_angle,
  shear_modulus,
  kc,
  kphi,
  c1,
  c2,
  slip_sinkage_n1,
  grouser_effectiveness,
  bulldozing_scale,
  soil_strength,
  shear_modulus_slip,
  rear_angle_ratio,
  lateral_shear_modulus,    // k_y of the slip-angle model (Ishigami et al. 2007)
  sidewall_scale,           // scale on its Hegedus sidewall term
  shear_residual_ratio,     // K_r of the peaked shear curve (Wong)
  shear_peak_displacement,  // its K_w, m
  rft_scale,                // zeta of the RFT family, N/m^3 (rft.h)
  rft_pileup,               // its pile-up fraction
  rft_depth_scale           // its depth-dependent scale
};
const char* to_string(Parameter p);
Parameter parse_parameter(const std::string& text);  // throws DataError

struct Bounds {
  double lower, upper;
};
Bounds default_bounds(Parameter p);  // physical ranges used unless overridden

struct IdentificationOptions {
  std::vector<Parameter> free;
  ModelOptions model;  // baseline model and the extensions switched on
  MeasurementSigma sigma;
  double huber_sigmas = 3.0;  // Huber loss threshold in sigmas; <= 0: plain least squares
  int max_iterations = 100;
  double tolerance = 1e-10;  // Ceres' function and parameter tolerance
  bool covariance = true;    // false: parameters' sigma left NaN (refits for held-out scores)
};

struct EstimatedParameter {
  Parameter parameter;
  double value = 0.0;
  double sigma = 0.0;  // +-1 sigma; NaN when the covariance is rank deficient
  Bounds bounds{0, 0};
  bool at_bound = false;
};

struct PointResidual {
  std::size_t point = 0;  // index into the points
  Quantity quantity = Quantity::drawbar_pull;
  double measured = 0.0;
  double predicted = 0.0;  // NaN where the model cannot carry the load
  double sigma = 1.0;
};

struct IdentificationResult {
  Soil soil;
  Extensions extensions;
  std::vector<EstimatedParameter> parameters;
  std::vector<PointResidual> residuals;
  double chi2 = 0.0;  // sum of squared normalised residuals at the solution
  std::size_t measurements = 0;
  bool converged = false;
  bool covariance_ok = false;
  // Correlations of the free parameters (k x k, row-major, in the order of
  // options.free); empty without the covariance.
  std::vector<double> correlation;
  std::string message;
};

// Reads and writes one parameter of (soil, extensions).
double get_parameter(const Soil& s, const Extensions& e, Parameter p);
void set_parameter(Soil& s, Extensions& e, Parameter p, double value);

// Starting from (soil, options.model.extensions), fits the free parameters to
// the measured quantities of `points`. Sigmas are scaled by
// sqrt(chi2 / (m - k)) when that exceeds one (scatter larger than claimed).
IdentificationResult identify_soil(const Soil& soil, const std::vector<WheelTestPoint>& points,
                                   const IdentificationOptions& options);

}  // namespace roverlab::terramechanics
