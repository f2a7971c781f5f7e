#pragma once
// Traction surfaces DP(W, s) and tau_R(W, s) as two-variable polynomials
// (seed 003 Eq. 2.28), fitted by weighted least squares, with the order
// chosen by cross-validation and an occupancy grid of the (W, s) data.

#include <cstddef>
#include <vector>

namespace roverlab::terramechanics {

struct SurfaceSample {
  double load;  // W, N
  double slip;  // s
  double value;
  double weight = 1.0;
};

// p_kl s^k W^l over k + l <= order, in the order of Eq. 2.28:
// p00, p10, p01, p20, p11, p02, p30, ...
class PolynomialSurface {
 public:
  PolynomialSurface() = default;
  PolynomialSurface(int order, std::vector<double> coefficients);
  int order() const { return order_; }
  const std::vector<double>& coefficients() const { return coefficients_; }
  double operator()(double load, double slip) const;
  // Exponents (k of slip, l of load) of coefficient i.
  static std::pair<int, int> exponents(std::size_t i);
  static std::size_t term_count(int order) { return static_cast<std::size_t>((order + 1) * (order + 2) / 2); }

 private:
  int order_ = 0;
  std::vector<double> coefficients_;
};

struct FitError {
  double mean_abs = 0.0;  // the "average error" of seed 003 section 2.6
  double rmse = 0.0;
  double max_abs = 0.0;
};

FitError fit_error(const PolynomialSurface& p, const std::vector<SurfaceSample>& samples);

// Weighted least squares of one order (1..6). Throws DataError when there
// are fewer samples than terms.
PolynomialSurface fit_surface(const std::vector<SurfaceSample>& samples, int order);

struct OrderScore {
  int order = 0;
  double train_rmse = 0.0;
  double cv_rmse = 0.0;  // k-fold cross-validation RMSE
};

struct SurfaceFit {
  PolynomialSurface surface;
  FitError error;                  // on the samples it was fitted to
  std::vector<OrderScore> orders;  // cross-validation table (empty for a fixed order)
};

// Fits orders 1..max_order, scores each by k-fold cross-validation (folds
// drawn with a fixed seed), and keeps the order with the lowest CV RMSE;
// among orders within 2 % of that, the lowest.
SurfaceFit fit_surface_cross_validated(const std::vector<SurfaceSample>& samples, int max_order = 6, int folds = 5,
                                       unsigned seed = 1);

// Counts of samples in a load x slip grid over the given ranges.
struct OccupancyGrid {
  double load_min = 0, load_max = 1, slip_min = 0, slip_max = 1;
  int load_bins = 10, slip_bins = 10;
  std::vector<int> counts;  // load-major: counts[l * slip_bins + s]

  static OccupancyGrid build(const std::vector<SurfaceSample>& samples, double load_min, double load_max,
                             double slip_min, double slip_max, int load_bins, int slip_bins);
  int count(int load_bin, int slip_bin) const {
    return counts[static_cast<std::size_t>(load_bin * slip_bins + slip_bin)];
  }
  double coverage() const;                       // fraction of cells with at least one sample
  bool covered(double load, double slip) const;  // the cell holding (load, slip) has data
};

}  // namespace roverlab::terramechanics
