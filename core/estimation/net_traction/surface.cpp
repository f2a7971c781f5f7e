#include "core/estimation/net_traction/surface.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <utility>

#include <Eigen/Dense>

#include "core/common/error.h"

namespace roverlab::analysis {

std::array<std::vector<bool>, 3> steady_state_mask(const std::vector<double>& time,
                                                   const std::array<std::vector<double>, 3>& wheel_acceleration,
                                                   const SteadyStateOptions& o) {
  std::array<std::vector<bool>, 3> mask;
  for (std::size_t w = 0; w < 3; ++w) {
    mask[w].assign(time.size(), false);
    for (std::size_t k = 0; k < time.size(); ++k) {
      const double a = wheel_acceleration[w][k];
      const bool in_window = o.window_seconds <= 0.0 || time[k] >= time.back() - o.window_seconds;
      mask[w][k] = in_window && time[k] - time.front() >= o.settle_seconds && std::abs(a) <= o.max_wheel_acceleration;
    }
  }
  return mask;
}

std::vector<TractionPoint> averaged_points(const std::vector<double>& time, const std::array<WheelSeries, 3>& wheels,
                                           const std::array<std::vector<bool>, 3>& mask, const SteadyStateOptions& o) {
  std::vector<TractionPoint> points;
  for (std::size_t w = 0; w < 3; ++w) {
    const WheelSeries& s = wheels[w];
    std::size_t k = 0;
    while (k < time.size()) {
      const double end = time[k] + o.average_seconds;
      TractionPoint sum;
      const bool has_x = s.x.size() == time.size();
      int n = 0;
      for (; k < time.size() && time[k] < end - 1e-9; ++k) {
        if (!mask[w][k]) continue;
        const double v[4] = {s.load[k], s.slip[k], s.drawbar_pull[k], s.resistive_torque[k]};
        if (!std::isfinite(v[0] + v[1] + v[2] + v[3])) continue;
        sum.load += v[0];
        sum.slip += v[1];
        sum.drawbar_pull += v[2];
        sum.resistive_torque += v[3];
        sum.time += time[k];
        if (has_x) sum.x += s.x[k];
        ++n;
      }
      if (n == 0) continue;
      const double inv = 1.0 / n;
      points.push_back({sum.load * inv, sum.slip * inv, sum.drawbar_pull * inv, sum.resistive_torque * inv,
                        static_cast<int>(w) + 1, sum.time * inv, sum.x * inv});
    }
  }
  return points;
}

std::vector<terramechanics::SurfaceSample> surface_samples(const std::vector<TractionPoint>& points,
                                                           TractionQuantity quantity) {
  std::vector<terramechanics::SurfaceSample> out;
  out.reserve(points.size());
  for (const auto& p : points) {
    out.push_back(
        {p.load, p.slip, quantity == TractionQuantity::drawbar_pull ? p.drawbar_pull : p.resistive_torque, 1.0});
  }
  return out;
}

TraversedRegion traversed_region(const std::vector<TractionPoint>& points, int bins) {
  if (points.size() < 10) {
    throw DataError("only " + std::to_string(points.size()) +
                    " steady-state points: too few to rebuild the traction surfaces");
  }
  TraversedRegion r;
  r.load_min = r.load_max = points.front().load;
  r.slip_min = r.slip_max = points.front().slip;
  for (const auto& p : points) {
    r.load_min = std::min(r.load_min, p.load);
    r.load_max = std::max(r.load_max, p.load);
    r.slip_min = std::min(r.slip_min, p.slip);
    r.slip_max = std::max(r.slip_max, p.slip);
  }
  if (!(r.load_max - r.load_min > 1e-6) || !(r.slip_max - r.slip_min > 1e-6)) {
    throw DataError("the steady-state points span a single load or slip: no surface to rebuild");
  }
  std::vector<terramechanics::SurfaceSample> s;
  s.reserve(points.size());
  for (const auto& p : points) s.push_back({p.load, p.slip, 0.0, 1.0});
  r.grid = terramechanics::OccupancyGrid::build(s, r.load_min, r.load_max, r.slip_min, r.slip_max, bins, bins);
  return r;
}

terramechanics::SurfaceFit fit_traction_surface(const std::vector<terramechanics::SurfaceSample>& samples, int order,
                                                int max_order) {
  if (order == 0) return terramechanics::fit_surface_cross_validated(samples, max_order);
  terramechanics::SurfaceFit fit;
  fit.surface = terramechanics::fit_surface(samples, order);
  fit.error = terramechanics::fit_error(fit.surface, samples);
  return fit;
}

SurfaceComparison compare_surfaces(const terramechanics::PolynomialSurface& estimate,
                                   const terramechanics::PolynomialSurface& reference, const TraversedRegion& region,
                                   int resolution) {
  SurfaceComparison c;
  double sum = 0, lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (int i = 0; i < resolution; ++i) {
    for (int j = 0; j < resolution; ++j) {
      const double W = region.load_min + (region.load_max - region.load_min) * (i + 0.5) / resolution;
      const double s = region.slip_min + (region.slip_max - region.slip_min) * (j + 0.5) / resolution;
      if (!region.grid.covered(W, s)) continue;
      const double ref = reference(W, s), d = estimate(W, s) - ref;
      sum += d * d;
      c.max_abs = std::max(c.max_abs, std::abs(d));
      lo = std::min(lo, ref);
      hi = std::max(hi, ref);
      ++c.grid_points;
    }
  }
  if (c.grid_points == 0) return c;
  c.rms = std::sqrt(sum / static_cast<double>(c.grid_points));
  c.range = hi - lo;
  if (c.range > 0) {
    c.rms_percent = 100.0 * c.rms / c.range;
    c.max_percent = 100.0 * c.max_abs / c.range;
  }
  return c;
}

namespace {

std::array<WheelSeries, 3> estimated_series(const estimation::NetTractionResult& r, const estimation::FilterTrack& w) {
  namespace gen = estimation::net_traction::general;
  namespace wf = estimation::net_traction::wheel_force;
  std::array<WheelSeries, 3> out;
  const auto n = static_cast<std::size_t>(r.general.state.rows());
  for (int i = 0; i < 3; ++i) {
    WheelSeries& s = out[static_cast<std::size_t>(i)];
    s.load.resize(n);
    s.slip.resize(n);
    s.drawbar_pull.resize(n);
    s.resistive_torque.resize(n);
    if (static_cast<std::size_t>(r.wheel_x.rows()) == n) s.x.resize(n);
    for (std::size_t k = 0; k < n; ++k) {
      const auto row = static_cast<Eigen::Index>(k);
      s.load[k] = w.state(row, wf::kNormalLoad + i);
      s.drawbar_pull[k] = w.state(row, wf::kDrawbarPull + i);
      s.slip[k] = r.general.state(row, gen::kSlip + i);
      s.resistive_torque[k] = r.general.state(row, gen::kResistiveTorque + i);
      if (!s.x.empty()) s.x[k] = r.wheel_x(row, i);
    }
  }
  return out;
}

// truth/wheels at the estimates' times; false without it.
bool truth_series(const log::Log& lg, const std::vector<double>& time, std::array<WheelSeries, 3>& out) {
  const log::Stream* t = lg.find_stream("truth/wheels");
  if (t == nullptr) return false;
  for (std::size_t i = 0; i < 3; ++i) {
    const std::string n = std::to_string(i + 1);
    for (const char* c : {"normal_load_", "slip_", "drawbar_pull_", "resistive_torque_"}) {
      if (t->find_channel(c + n) == nullptr) return false;
    }
    out[i].load = t->interpolate("normal_load_" + n, time);
    out[i].slip = t->interpolate("slip_" + n, time);
    out[i].drawbar_pull = t->interpolate("drawbar_pull_" + n, time);
    out[i].resistive_torque = t->interpolate("resistive_torque_" + n, time);
  }
  return true;
}

QuantityFit fit_quantity(const std::vector<TractionPoint>& estimated, const std::vector<TractionPoint>* truth,
                         const TraversedRegion& region, TractionQuantity quantity, int order, int max_order) {
  QuantityFit f;
  f.estimate = fit_traction_surface(surface_samples(estimated, quantity), order, max_order);
  if (truth != nullptr && truth->size() >= terramechanics::PolynomialSurface::term_count(f.estimate.surface.order())) {
    f.truth = fit_traction_surface(surface_samples(*truth, quantity), f.estimate.surface.order(), max_order);
    f.comparison = compare_surfaces(f.estimate.surface, f.truth.surface, region);
    f.has_truth = true;
  }
  return f;
}

}  // namespace

NetTractionModel rebuild_net_traction_model(const log::Log& lg, const estimation::NetTractionResult& r,
                                            const estimation::FilterTrack& w, const SteadyStateOptions& o, int order,
                                            int max_order) {
  std::array<std::vector<double>, 3> acceleration;
  for (int i = 0; i < 3; ++i) {
    const Eigen::VectorXd c = r.wheel_acceleration.col(i);
    acceleration[static_cast<std::size_t>(i)].assign(c.data(), c.data() + c.size());
  }
  const auto mask = steady_state_mask(r.time, acceleration, o);
  NetTractionModel m;
  for (const auto& wm : mask) m.kept_samples += static_cast<std::size_t>(std::count(wm.begin(), wm.end(), true));
  const std::vector<TractionPoint> points = averaged_points(r.time, estimated_series(r, w), mask, o);
  m.points = points.size();
  m.estimated_points = points;
  m.region = traversed_region(points);
  std::array<WheelSeries, 3> truth;
  std::vector<TractionPoint> truth_points;
  const bool has_truth = truth_series(lg, r.time, truth);
  if (has_truth) truth_points = averaged_points(r.time, truth, mask, o);
  const std::vector<TractionPoint>* tp = has_truth ? &truth_points : nullptr;
  m.drawbar_pull = fit_quantity(points, tp, m.region, TractionQuantity::drawbar_pull, order, max_order);
  m.resistive_torque = fit_quantity(points, tp, m.region, TractionQuantity::resistive_torque, order, max_order);
  if (r.wheel_x.rows() > 0 && !r.time.empty()) {
    ChangeDetectorOptions c;
    c.ignore_before = r.time.front() + kChangeSettleSeconds;
    m.changes = detect_traction_changes(points, c);
  }
  return m;
}

namespace {

constexpr int kShapeOrder = 2;

// The steady-state points of a pass's single-axis estimates, as
// rebuild_net_traction_model averages them.
std::vector<TractionPoint> single_axis_points(const estimation::NetTractionResult& pass,
                                              const SteadyStateOptions& steady) {
  std::array<std::vector<double>, 3> acceleration;
  for (int i = 0; i < 3; ++i) {
    const Eigen::VectorXd c = pass.wheel_acceleration.col(i);
    acceleration[static_cast<std::size_t>(i)].assign(c.data(), c.data() + c.size());
  }
  return averaged_points(pass.time, estimated_series(pass, pass.single_axis),
                         steady_state_mask(pass.time, acceleration, steady), steady);
}

}  // namespace

double single_axis_drawbar_pull_fit_rmse(const estimation::NetTractionResult& pass, const SteadyStateOptions& steady) {
  const std::vector<TractionPoint> points = single_axis_points(pass, steady);
  return fit_traction_surface(surface_samples(points, TractionQuantity::drawbar_pull), kShapeOrder).error.rmse;
}

estimation::NetTractionResult single_axis_second_pass(const log::Log& lg,
                                                      const estimation::net_traction::RoverConstants& rover,
                                                      const estimation::NetTractionOptions& options,
                                                      const estimation::NetTractionResult& first_pass,
                                                      const SteadyStateOptions& steady) {
  const std::vector<TractionPoint> points = single_axis_points(first_pass, steady);
  const TraversedRegion region = traversed_region(points);
  const terramechanics::PolynomialSurface shape =
      fit_traction_surface(surface_samples(points, TractionQuantity::drawbar_pull), kShapeOrder).surface;
  estimation::NetTractionOptions o = options;
  o.force_sensors = estimation::ForceSensors::single_axis;
  o.bogie_split_shape = [shape, region](double load, double slip) {
    return shape(std::clamp(load, region.load_min, region.load_max),
                 std::clamp(slip, region.slip_min, region.slip_max));
  };
  return estimation::run_net_traction(lg, rover, o);
}

namespace {

// tau = 1 + 2 sum_k rho_k (k >= 1, while rho_k > 0: Geyer's initial positive
// sequence) of the normalised residuals, pooled over the sequences of one
// wheel and one quantity (residuals in point order, points in time order).
double residual_correlation_factor(const std::vector<terramechanics::PointResidual>& residuals,
                                   const std::vector<int>& wheel_of_point) {
  std::map<std::pair<int, int>, std::vector<double>> sequences;
  for (const auto& r : residuals) {
    const double z = (r.predicted - r.measured) / r.sigma;
    if (!std::isfinite(z)) continue;
    sequences[{wheel_of_point[r.point], static_cast<int>(r.quantity)}].push_back(z);
  }
  double c0 = 0.0;
  std::size_t longest = 0;
  for (const auto& entry : sequences) {
    for (double z : entry.second) c0 += z * z;
    longest = std::max(longest, entry.second.size());
  }
  if (!(c0 > 0.0)) return 1.0;
  double tau = 1.0;
  for (std::size_t lag = 1; lag < longest / 2; ++lag) {
    double ck = 0.0;
    for (const auto& entry : sequences) {
      const std::vector<double>& z = entry.second;
      for (std::size_t i = 0; i + lag < z.size(); ++i) ck += z[i] * z[i + lag];
    }
    if (!(ck > 0.0)) break;
    tau += 2.0 * ck / c0;
  }
  return tau;
}

}  // namespace

SoilFromRover identify_soil_from_points(const std::vector<TractionPoint>& points, const terramechanics::Soil& start,
                                        const terramechanics::Wheel& wheel,
                                        const std::vector<terramechanics::Parameter>& free, std::size_t max_points) {
  if (points.size() < 10) throw DataError("too few steady-state points to fit the soil");
  std::vector<terramechanics::WheelTestPoint> test;
  std::vector<int> wheel_of_point;
  const std::size_t stride = std::max<std::size_t>(1, (points.size() + max_points - 1) / max_points);
  for (std::size_t i = 0; i < points.size(); i += stride) {
    terramechanics::WheelTestPoint p;
    p.wheel = wheel;
    p.wheel_label = "wheel " + std::to_string(points[i].wheel);
    p.load = points[i].load;
    p.slip = points[i].slip;
    p.drawbar_pull = points[i].drawbar_pull;
    p.torque = points[i].resistive_torque;
    test.push_back(p);
    wheel_of_point.push_back(points[i].wheel);
  }
  terramechanics::IdentificationOptions o;
  o.free = free;
  o.sigma.drawbar_pull = 0.5;  // N: about the drawbar pulls' tracking error
  o.sigma.torque = 0.02;       // N m: the resistive torques' scatter about a surface
  SoilFromRover out;
  out.points = test.size();
  out.fit = terramechanics::identify_soil(start, test, o);
  const std::size_t k = free.size();
  if (out.fit.measurements > k) {
    // identify_soil widened the sigmas by sqrt(max(1, chi2 / (m - k))).
    out.reduced_chi2 = out.fit.chi2 / static_cast<double>(out.fit.measurements - k);
    out.correlation_factor = residual_correlation_factor(out.fit.residuals, wheel_of_point);
    const double scale = std::sqrt(out.reduced_chi2 * out.correlation_factor / std::max(1.0, out.reduced_chi2));
    for (auto& e : out.fit.parameters) e.sigma *= scale;
  }
  if (out.fit.correlation.size() == k * k) {
    for (std::size_t i = 0; i < k; ++i) {
      for (std::size_t j = i + 1; j < k; ++j) {
        if (std::abs(out.fit.correlation[i * k + j]) > 0.95) out.confounded.emplace_back(free[i], free[j]);
      }
    }
  }
  return out;
}

namespace {

// Residual sums of squares of Eq. 2.28 fits to the first k points (k = 0..n)
// of a sequence, for DP and tau_R, by accumulated normal equations (W and s
// scaled to about [-1, 1]: the polynomial space is the same).
class PrefixFits {
 public:
  PrefixFits(int order, double load_mid, double load_half, double slip_mid, double slip_half)
      : order_(std::clamp(order, 1, 6)),
        load_mid_(load_mid),
        load_half_(load_half),
        slip_mid_(slip_mid),
        slip_half_(slip_half) {
    const auto p = static_cast<Eigen::Index>(terramechanics::PolynomialSurface::term_count(order_));
    A_ = Eigen::MatrixXd::Zero(p, p);
    b_ = Eigen::MatrixXd::Zero(p, 2);
    phi_.resize(p);
  }
  void add(const TractionPoint& pt) {
    const double w = (pt.load - load_mid_) / load_half_, s = (pt.slip - slip_mid_) / slip_half_;
    std::array<double, 8> sk{}, wl{};  // powers 0..order (at most 6)
    sk[0] = wl[0] = 1.0;
    for (int p = 1; p <= order_; ++p) {
      sk[static_cast<std::size_t>(p)] = sk[static_cast<std::size_t>(p - 1)] * s;
      wl[static_cast<std::size_t>(p)] = wl[static_cast<std::size_t>(p - 1)] * w;
    }
    for (Eigen::Index i = 0; i < phi_.size(); ++i) {
      const auto [k, l] = terramechanics::PolynomialSurface::exponents(static_cast<std::size_t>(i));
      phi_(i) = sk[static_cast<std::size_t>(k)] * wl[static_cast<std::size_t>(l)];
    }
    A_.selfadjointView<Eigen::Lower>().rankUpdate(phi_);
    const Eigen::Vector2d y(pt.drawbar_pull, pt.resistive_torque);
    b_ += phi_ * y.transpose();
    yy_ += y.cwiseProduct(y);
  }
  // RSS of DP and tau_R fitted to the points added so far.
  Eigen::Vector2d rss() const {
    Eigen::MatrixXd A = A_.selfadjointView<Eigen::Lower>();
    A.diagonal().array() += 1e-10 * (1.0 + A.diagonal().maxCoeff());
    const Eigen::MatrixXd coef = A.ldlt().solve(b_);
    Eigen::Vector2d out;
    for (int q = 0; q < 2; ++q) out(q) = std::max(yy_(q) - b_.col(q).dot(coef.col(q)), 0.0);
    return out;
  }

 private:
  int order_;
  double load_mid_, load_half_, slip_mid_, slip_half_;
  Eigen::MatrixXd A_, b_;
  Eigen::VectorXd phi_;
  Eigen::Vector2d yy_ = Eigen::Vector2d::Zero();
};

// lambda at x: the points within window of x on either side, fitted by one
// surface and by two split at x (see the header); -1 with too few points.
double split_statistic(const std::vector<TractionPoint>& sorted, double x, const ChangeDetectorOptions& o) {
  const auto by_x = [](const TractionPoint& p, double v) { return p.x < v; };
  const auto lo = std::lower_bound(sorted.begin(), sorted.end(), x - o.window, by_x);
  const auto mid = std::lower_bound(lo, sorted.end(), x, by_x);
  const auto hi = std::lower_bound(mid, sorted.end(), x + o.window, by_x);
  if (static_cast<std::size_t>(mid - lo) < o.min_points || static_cast<std::size_t>(hi - mid) < o.min_points) {
    return -1.0;
  }
  // Each side seen by at least two wheels: one wheel alone spans a narrow
  // band of loads (the start and the end of a run).
  const auto wheels = [&](auto a, auto b) {
    std::array<std::size_t, 3> n{};
    for (auto it = a; it != b; ++it) ++n[static_cast<std::size_t>(std::clamp(it->wheel, 1, 3) - 1)];
    return std::count_if(n.begin(), n.end(), [&](std::size_t c) { return c >= o.min_wheel_points; });
  };
  if (wheels(lo, mid) < 2 || wheels(mid, hi) < 2) return -1.0;
  double wl = lo->load, wh = wl, sl = lo->slip, sh = sl;
  for (auto it = lo; it != hi; ++it) {
    wl = std::min(wl, it->load);
    wh = std::max(wh, it->load);
    sl = std::min(sl, it->slip);
    sh = std::max(sh, it->slip);
  }
  const auto fits = [&] {
    return PrefixFits(o.order, 0.5 * (wl + wh), std::max(0.5 * (wh - wl), 1e-9), 0.5 * (sl + sh),
                      std::max(0.5 * (sh - sl), 1e-9));
  };
  PrefixFits one = fits(), before = fits(), after = fits();
  for (auto it = lo; it != hi; ++it) {
    one.add(*it);
    (it < mid ? before : after).add(*it);
  }
  const Eigen::Vector2d r1 = one.rss(), r2 = before.rss() + after.rss();
  double lambda = 0;
  for (int q = 0; q < 2; ++q) lambda += std::log(std::max(r1(q), 1e-300) / std::max(r2(q), 1e-300));
  return lambda;
}

}  // namespace

ChangeDetection detect_traction_changes(const std::vector<TractionPoint>& points, const ChangeDetectorOptions& o) {
  ChangeDetection out;
  std::vector<TractionPoint> sorted;
  sorted.reserve(points.size());
  for (const auto& p : points) {
    if (p.time >= o.ignore_before && std::isfinite(p.x + p.load + p.slip + p.drawbar_pull + p.resistive_torque)) {
      sorted.push_back(p);
    }
  }
  std::stable_sort(sorted.begin(), sorted.end(),
                   [](const TractionPoint& a, const TractionPoint& b) { return a.x < b.x; });
  out.points = sorted.size();
  double front_lo = HUGE_VAL, front_hi = -HUGE_VAL;
  for (const auto& p : sorted) {
    if (p.wheel != 1) continue;
    front_lo = std::min(front_lo, p.x);
    front_hi = std::max(front_hi, p.x);
  }
  if (!(front_hi - front_lo >= o.min_path)) {
    char why[160];
    std::snprintf(why, sizeof why, "the front wheel's points span %.2f m of path; the scan needs %.2f m",
                  std::max(front_hi - front_lo, 0.0), o.min_path);
    out.not_run = why;
    return out;
  }
  // lambda on a grid of positions along the path.
  std::vector<std::pair<double, double>> scan;  // (x, lambda)
  for (double x = sorted.front().x + o.step; x < sorted.back().x; x += o.step) {
    const double lambda = split_statistic(sorted, x, o);
    if (lambda < 0) continue;
    scan.emplace_back(x, lambda);
    if (lambda > out.largest_statistic) {
      out.largest_statistic = lambda;
      out.largest_at = x;
    }
  }
  // The largest peaks above the threshold, at least a window apart.
  std::vector<char> used(scan.size(), 0);
  while (static_cast<int>(out.changes.size()) < o.max_changes) {
    std::size_t best = scan.size();
    for (std::size_t i = 0; i < scan.size(); ++i) {
      if (!used[i] && (best == scan.size() || scan[i].second > scan[best].second)) best = i;
    }
    if (best == scan.size() || !(scan[best].second > o.threshold)) break;
    const double x = scan[best].first;
    for (std::size_t i = 0; i < scan.size(); ++i) {
      if (std::abs(scan[i].first - x) < o.window) used[i] = 1;
    }
    ChangePoint c;
    c.x = x;
    c.statistic = scan[best].second;
    const auto by_x = [](const TractionPoint& p, double v) { return p.x < v; };
    const auto mid = std::lower_bound(sorted.begin(), sorted.end(), x, by_x);
    c.before = static_cast<std::size_t>(mid - std::lower_bound(sorted.begin(), mid, x - o.window, by_x));
    c.after = static_cast<std::size_t>(std::lower_bound(mid, sorted.end(), x + o.window, by_x) - mid);
    c.front_wheel_time = NAN;
    for (const auto& p : sorted) {
      if (p.wheel == 1 && p.x >= x && (std::isnan(c.front_wheel_time) || p.time < c.front_wheel_time)) {
        c.front_wheel_time = p.time;
      }
    }
    out.changes.push_back(c);
  }
  std::sort(out.changes.begin(), out.changes.end(),
            [](const ChangePoint& a, const ChangePoint& b) { return a.x < b.x; });
  return out;
}

std::string surface_term(std::size_t i) {
  const auto [k, l] = terramechanics::PolynomialSurface::exponents(i);
  const auto power = [](const char* v, int n) {
    if (n == 0) return std::string();
    return n == 1 ? std::string(v) : std::string(v) + "^" + std::to_string(n);
  };
  std::string t = power("s", k);
  const std::string w = power("W", l);
  if (!t.empty() && !w.empty()) t += " ";
  t += w;
  return t.empty() ? "1" : t;
}

BogieSplitChoice choose_bogie_split(const log::Log& lg, const estimation::net_traction::RoverConstants& rover,
                                    const estimation::NetTractionOptions& options, BogieSplit split,
                                    const SteadyStateOptions& steady, estimation::NetTractionResult& r) {
  BogieSplitChoice choice;
  if (split == BogieSplit::eq_5_66 || r.single_axis.empty()) return choice;
  try {
    estimation::NetTractionResult second = single_axis_second_pass(lg, rover, options, r, steady);
    choice.shape = true;
    if (split == BogieSplit::automatic) {  // keep the second pass only if its points stay as consistent
      choice.compared = true;
      choice.first_pass_fit_rmse = single_axis_drawbar_pull_fit_rmse(r, steady);
      choice.second_pass_fit_rmse = single_axis_drawbar_pull_fit_rmse(second, steady);
      choice.shape = choice.second_pass_fit_rmse < kSecondPassFitGrowthLimit * choice.first_pass_fit_rmse;
    }
    if (choice.shape && r.force_sensors == estimation::ForceSensors::single_axis) {
      r = std::move(second);
    } else if (choice.shape) {
      r.single_axis = std::move(second.single_axis);
      r.rejected_updates[2] = second.rejected_updates[2];
    }
  } catch (const DataError&) {  // too few points for the shape: Eq. 5.66 alone (the fits say why)
    choice.shape = false;
  }
  return choice;
}

bool drives(const log::Stream& velocimeter, double speed) {
  const auto& v = velocimeter.channel("forward_speed").values;
  const auto& t = velocimeter.time();
  const auto value = [&](std::size_t k) { return std::isfinite(v[k]) ? v[k] : 0.0; };
  double sum = 0;
  std::size_t first = 0;
  for (std::size_t k = 0; k < v.size(); ++k) {  // a moving mean over one second
    sum += value(k);
    for (; t[k] - t[first] > 1.0; ++first) sum -= value(first);
    const auto n = static_cast<double>(k - first + 1);
    if (t[k] - t[first] >= 0.9 && std::abs(sum) > speed * n) return true;
  }
  return false;
}

}  // namespace roverlab::analysis
