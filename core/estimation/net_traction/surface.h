#pragma once
// The net traction model of seed 003 section 5.7: estimated points (W, s,
// DP, tau_R) kept where the rover is near steady state (the seed's filter on
// the estimated wheel accelerations) and averaged in time, the Eq. 2.28
// polynomial fitted to them (order given or by cross-validation), the region
// of load and slip they cover (the occupancy grid), and the comparison with
// the true local model (the same fit to the truth over the same region),
// as section 5.8 and Table 5.2 compare them.

#include <array>
#include <cmath>
#include <cstddef>
#include <string>
#include <vector>

#include "core/estimation/net_traction/net_traction.h"
#include "core/log/log.h"
#include "core/terramechanics/soil_identification.h"
#include "core/terramechanics/traction_surface.h"

namespace roverlab::analysis {

// One wheel's series on a common time base; x (the wheel centre's position
// along the path, m) may be empty.
struct WheelSeries {
  std::vector<double> load, slip, drawbar_pull, resistive_torque, x;
};

struct SteadyStateOptions {
  // Section 5.8: points where an estimated wheel acceleration exceeds this are left out.
  double max_wheel_acceleration = 6.079e-3;  // rad/s^2
  double average_seconds = 0.2;              // section 5.8: averaged to 5 samples/s
  double settle_seconds = 5.0;               // the filters' convergence at the start is left out
  double window_seconds = 0.0;               // section 5.9: only the last this many seconds (0: all)
};

// Which samples of each wheel are near steady state (|wheel acceleration| below the threshold, after the settling).
std::array<std::vector<bool>, 3> steady_state_mask(const std::vector<double>& time,
                                                   const std::array<std::vector<double>, 3>& wheel_acceleration,
                                                   const SteadyStateOptions& options);

struct TractionPoint {
  double load = 0, slip = 0, drawbar_pull = 0, resistive_torque = 0;
  int wheel = 0;
  double time = 0, x = 0;  // s, and m along the path (0 when the series has no x)
};

// The kept samples of every wheel averaged over consecutive windows of
// average_seconds (a window with no kept sample gives no point).
std::vector<TractionPoint> averaged_points(const std::vector<double>& time, const std::array<WheelSeries, 3>& wheels,
                                           const std::array<std::vector<bool>, 3>& mask,
                                           const SteadyStateOptions& options);

enum class TractionQuantity { drawbar_pull, resistive_torque };
std::vector<terramechanics::SurfaceSample> surface_samples(const std::vector<TractionPoint>& points,
                                                           TractionQuantity quantity);

// The load and slip the points cover, with an occupancy grid over them.
struct TraversedRegion {
  double load_min = 0, load_max = 0, slip_min = 0, slip_max = 0;
  terramechanics::OccupancyGrid grid;
};
// Throws DataError with fewer than 10 points or a region of zero width.
TraversedRegion traversed_region(const std::vector<TractionPoint>& points, int bins = 8);

// Eq. 2.28 of the given order (1..6), or (order 0) the order 1..max_order
// with the best cross-validated RMS.
terramechanics::SurfaceFit fit_traction_surface(const std::vector<terramechanics::SurfaceSample>& samples, int order,
                                                int max_order = 4);

// Two surfaces over the covered cells of a region, on a fine grid: RMS and
// largest difference, and both in % of the reference's range there.
struct SurfaceComparison {
  double rms = 0, max_abs = 0, range = 0, rms_percent = 0, max_percent = 0;
  std::size_t grid_points = 0;
};
SurfaceComparison compare_surfaces(const terramechanics::PolynomialSurface& estimate,
                                   const terramechanics::PolynomialSurface& reference, const TraversedRegion& region,
                                   int resolution = 40);

// Section 5.9 (issue 12 item 6): where along the path the traction
// relationship changed. Each point sits at its own wheel's x, so a split at
// X puts a wheel's points after it once that wheel has passed X. Statistic,
// on the points within `window` of X on either side: the log-likelihood
// ratio, per point, of two Eq. 2.28 surfaces (before and after X) against
// one, for DP and for tau_R with Gaussian residuals of unknown variance,
// lambda(X) = sum over the two quantities of ln(RSS_one / (RSS_before +
// RSS_after)). It is scanned along the path every `step` (at least
// min_points on each side); a change is a peak above `threshold`, the next
// one at least a window away from it.
struct ChangeDetectorOptions {
  int order = 3;           // of the surfaces: over a window, order 2 leaves more misfit to mistake for a change
  double window = 0.7;     // m either side of X
  double step = 0.01;      // m
  double threshold = 2.4;  // on lambda (calibration: docs/validation/net-traction.md)
  double ignore_before = -HUGE_VAL;  // s: points earlier than this are left out (the filters' convergence)
  std::size_t min_points = 50;
  std::size_t min_wheel_points = 20;  // on each side, from at least two wheels
  // The front wheel's points must span this much path (m): on shorter runs
  // the scan's no-change values reach the threshold (calibration).
  double min_path = 1.1;
  int max_changes = 3;
};
struct ChangePoint {
  double x = 0;                 // m: along the path (the wheels' x)
  double front_wheel_time = 0;  // s: the first point of wheel 1 at or past x (NaN if none)
  double statistic = 0;         // lambda there
  std::size_t before = 0, after = 0;
};
struct ChangeDetection {
  std::vector<ChangePoint> changes;  // sorted by x
  double largest_statistic = 0;      // lambda's largest value (the evidence when there is no change)
  double largest_at = 0;             // m, where it was
  std::size_t points = 0;
  std::string not_run;  // why the scan did not run (empty when it did)
};
ChangeDetection detect_traction_changes(const std::vector<TractionPoint>& points,
                                        const ChangeDetectorOptions& options = {});

// One quantity's surface rebuilt from the estimates and, with truth, the
// true local model of the same order over the same region.
struct QuantityFit {
  terramechanics::SurfaceFit estimate, truth;
  bool has_truth = false;
  SurfaceComparison comparison;
};
struct NetTractionModel {
  std::size_t points = 0, kept_samples = 0;
  std::vector<TractionPoint> estimated_points;  // the averaged steady-state points
  TraversedRegion region;
  QuantityFit drawbar_pull, resistive_torque;
  // Section 5.9 on estimated_points (x from NetTractionResult::wheel_x),
  // leaving out the first kChangeSettleSeconds of the log.
  ChangeDetection changes;
};
constexpr double kChangeSettleSeconds = 20.0;
// Section 5.7 on one wheel-force estimator's output (Estimator 1's slips
// and resistive torques with its loads and drawbar pulls): order 0 chooses
// by cross-validation. Throws DataError when too few points remain.
NetTractionModel rebuild_net_traction_model(const log::Log& log, const estimation::NetTractionResult& result,
                                            const estimation::FilterTrack& wheel_forces,
                                            const SteadyStateOptions& options, int order, int max_order = 4);

// Section 5.6's single-axis estimator in two passes: pass 1 (first_pass,
// Eq. 5.66: the bogie's perpendicular load split in proportion to the
// sensed loads); pass 2 runs Estimators 1 and 3 again with the split from
// the order-2 DP(W, s) surface fitted to pass 1's steady-state points (all
// wheels), held at the edge of their region beyond it
// (net_traction::perpendicular_from_net_forces with a shape). Throws
// DataError when pass 1 leaves too few points.
estimation::NetTractionResult single_axis_second_pass(const log::Log& log,
                                                      const estimation::net_traction::RoverConstants& rover,
                                                      const estimation::NetTractionOptions& options,
                                                      const estimation::NetTractionResult& first_pass,
                                                      const SteadyStateOptions& steady);

// RMS residual of the order-2 DP(W, s) surface fitted to a pass's
// single-axis steady-state points (all wheels): how consistent with one
// smooth surface the pass's drawbar pulls are. Throws DataError when there
// are too few points.
double single_axis_drawbar_pull_fit_rmse(const estimation::NetTractionResult& pass, const SteadyStateOptions& steady);

// The second pass is kept when its fit RMS grows by less than this factor
// over the first's (measured: 4-10 % where the second pass is closer to the
// true local model, 39-56 % where it is further; docs/validation/net-traction.md).
constexpr double kSecondPassFitGrowthLimit = 1.25;

// How the single-axis estimator splits the bogie's perpendicular load
// (section 5.6): Eq. 5.66 alone, the second pass's shape, or the shape only
// when its DP fit stays within kSecondPassFitGrowthLimit of the first's.
enum class BogieSplit { eq_5_66, shape, automatic };

// What choose_bogie_split decided, and on what evidence (auto only).
struct BogieSplitChoice {
  bool shape = false;                                            // the second pass's split was kept
  bool compared = false;                                         // auto compared the two passes' fits
  double first_pass_fit_rmse = NAN, second_pass_fit_rmse = NAN;  // N, when compared
};

// Section 5.6 in two passes when `split` asks for it and `result` has a
// single-axis estimator: runs single_axis_second_pass and, when the split is
// kept, puts its single-axis estimates (all of the result, when the rover has
// single-axis sensors only) into `result`. Too few points for the shape
// leaves Eq. 5.66's pass.
BogieSplitChoice choose_bogie_split(const log::Log& log, const estimation::net_traction::RoverConstants& rover,
                                    const estimation::NetTractionOptions& options, BogieSplit split,
                                    const SteadyStateOptions& steady, estimation::NetTractionResult& result);

// Whether the forward speed averaged over some second exceeds `speed` (m/s;
// a single sample may, by the velocimeter's noise alone): the rover drives,
// so there are traction points to estimate.
bool drives(const log::Stream& velocimeter, double speed = 2e-3);

// Issue 12 item 5: soil parameters fitted (Ceres, core/terramechanics/
// soil_identification.h) to the estimated steady-state points (drawbar pull
// and resistive torque at each load and slip), from `start`, with +-1
// sigma, correlations, and the pairs the points cannot tell apart
// (|correlation| above 0.95). At most max_points points (evenly spaced).
// The sigmas account for the points' errors: scaled to the residuals' own
// variance (chi2 / (m - k), down as well as up) and widened by sqrt(tau),
// tau = 1 + 2 sum_k rho_k of the residuals' autocorrelation along each
// wheel's points (the estimates' errors and the model's misfit persist over
// many points: m points carry the information of about m / tau).
struct SoilFromRover {
  terramechanics::IdentificationResult fit;
  std::vector<std::pair<terramechanics::Parameter, terramechanics::Parameter>> confounded;
  std::size_t points = 0;
  double reduced_chi2 = 1.0;        // chi2 / (m - k) at the solution
  double correlation_factor = 1.0;  // tau
};
SoilFromRover identify_soil_from_points(const std::vector<TractionPoint>& points, const terramechanics::Soil& start,
                                        const terramechanics::Wheel& wheel,
                                        const std::vector<terramechanics::Parameter>& free,
                                        std::size_t max_points = 300);

// The Eq. 2.28 term of coefficient i, e.g. "s^2 W" (p_21).
std::string surface_term(std::size_t i);

}  // namespace roverlab::analysis
