#pragma once
// Plate-sinkage (bevameter) tests: a plate pushed into soil, its force against
// its depth. Finds the contact instant, tells loading from unloading, and fits
// the pressure-sinkage relations of Bekker, Reece and resistive force theory
// (RFT) to the virgin loading samples with Ceres (+-1 sigma from
// ceres::Covariance, scaled by the residual scatter) and a held-out error.
// SI units: depth in m (positive into the soil), force in N, pressure in Pa.

#include <cstddef>
#include <string>
#include <vector>

namespace roverlab::terramechanics {

// A rectangular plate (width <= length) or a circular one (its diameter).
struct Plate {
  bool circular = true;
  double width = 0.1;   // m: the diameter of a circular plate
  double length = 0.1;  // m: rectangular plates only
  // Bekker's b: the smaller side of a rectangle, the radius of a circle (Wong, Theory of Ground Vehicles, 2008, Ch. 2).
  double b() const { return circular ? width / 2 : width; }
  double area() const;
};

struct PlateRecord {
  std::string name;  // the file it came from
  Plate plate;
  std::vector<double> depth;  // m, positive into the soil
  std::vector<double> force;  // N, positive when the soil pushes back
};

enum class PlateSegmentKind { approach, loading, unloading, reloading };
const char* to_string(PlateSegmentKind kind);

struct PlateSegment {
  PlateSegmentKind kind = PlateSegmentKind::approach;
  std::size_t begin = 0, end = 0;  // samples [begin, end)
};

struct PlateSegmentation {
  double force_noise = 0.0;      // N: robust scatter of the force's sample-to-sample changes / sqrt(2)
  double contact_threshold = 0;  // N: the force that says the plate touches
  std::size_t contact = 0;       // first sample over the threshold
  bool contact_seen = false;     // false: the record starts in contact
  std::vector<PlateSegment> segments;
  std::vector<std::size_t> virgin;  // loading samples deeper than any before: the fitted ones
};

// Throws DataError (naming the record) when the record is too short, has
// unequal columns, or never rises above its noise.
PlateSegmentation segment_plate_record(const PlateRecord& record);

enum class PressureModel { bekker, reece, rft };
const char* to_string(PressureModel model);

struct PlateParameter {
  std::string name, unit;
  double value = 0.0;
  double sigma = 0.0;  // +-1 sigma; NaN without a covariance or at a bound
  bool at_bound = false;
};

struct PressureSinkageFit {
  PressureModel model = PressureModel::bekker;
  bool sizes_separated = true;  // false: one plate size, one lumped modulus
  std::vector<PlateParameter> parameters;
  std::vector<double> contact_depths;  // m, one per record (fitted)
  std::size_t samples = 0;
  double rmse_N = 0.0;
  double held_out_rmse_N = 0.0;  // contiguous depth folds, each predicted by a fit without it
  bool converged = false;
  bool covariance_ok = false;
  std::string note;
  const PlateParameter* find(const std::string& name) const;
};

struct PlateFitOptions {
  double cohesion = 0.0;     // Pa: divides Reece's c k'_c into k'_c (0: k'_c not given)
  double unit_weight = 0.0;  // N/m^3 (rho g): divides Reece's gamma k'_phi into k'_phi
  int folds = 5;             // held-out folds
};

struct PlateAnalysis {
  std::vector<PlateSegmentation> records;
  std::vector<double> plate_sizes;       // distinct b, m
  std::vector<PressureSinkageFit> fits;  // bekker, reece, rft
};

// The force (N) a fitted relation gives `plate` at `depth` (m) in a record
// whose fitted contact depth is `contact_depth` (0 above it): the curve a
// view draws through the record's samples.
double fitted_force(const PressureSinkageFit& fit, const Plate& plate, double contact_depth, double depth);

// Throws DataError naming the problem (no record, a record without contact).
PlateAnalysis analyse_plate_tests(const std::vector<PlateRecord>& records, const PlateFitOptions& options);

// Pressure on a plate at sinkage z (m): Bekker (Wong 2008, Ch. 2),
// Reece (Reece 1965; k1 = c k'_c, k2 = gamma_s k'_phi) and RFT (Li 2013:
// sigma_z = zeta |alpha_z(0, pi/2)| z, horizontal plate pushed down, alpha_z
// the RFT family's own generic coefficient, rft.h generic_alpha).
double bekker_pressure(double kc, double kphi, double n, double b, double z);
double reece_pressure(double k1, double k2, double n, double b, double z);
double rft_pressure(double zeta, double z);

}  // namespace roverlab::terramechanics
