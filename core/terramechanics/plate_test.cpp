#include "core/terramechanics/plate_test.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numeric>
#include <set>

#include <ceres/ceres.h>

#include "core/common/error.h"
#include "core/terramechanics/rft.h"

namespace roverlab::terramechanics {

double Plate::area() const { return circular ? M_PI * width * width / 4 : width * length; }

const char* to_string(PlateSegmentKind kind) {
  switch (kind) {
    case PlateSegmentKind::approach:
      return "approach";
    case PlateSegmentKind::loading:
      return "loading";
    case PlateSegmentKind::unloading:
      return "unloading";
    case PlateSegmentKind::reloading:
      return "reloading";
  }
  return "?";
}

const char* to_string(PressureModel model) {
  switch (model) {
    case PressureModel::bekker:
      return "bekker";
    case PressureModel::reece:
      return "reece";
    case PressureModel::rft:
      return "rft";
  }
  return "?";
}

const PlateParameter* PressureSinkageFit::find(const std::string& name) const {
  for (const auto& p : parameters) {
    if (p.name == name) return &p;
  }
  return nullptr;
}

namespace {

constexpr double kPaPerNcm3 = 1e6;    // 1 N/cm^3 = 1e6 N/m^3: alpha z in Pa for z in m
constexpr double kDepthScale = 1e-3;  // contact depths fitted in mm

// |alpha_z| of a horizontal plate moving straight down, N/cm^3 per unit zeta.
double rft_plate_alpha() { return std::abs(generic_alpha(0.0, M_PI / 2).z); }  // Li 2013 Eq. S2, Table S2

// Which relation and how many of its moduli the plate sizes can tell apart.
struct Shape {
  PressureModel model;
  bool separated;
  int size() const { return model == PressureModel::rft ? 1 : separated ? 3 : 2; }
};

template <class T>
T model_pressure(const Shape& s, const T* x, double b, const T& z) {
  using std::pow;
  if (!(z > T(0))) return T(0);
  switch (s.model) {
    case PressureModel::bekker:  // Bekker (1969), Wong 2008 Ch. 2: p = (k_c / b + k_phi) z^n
      return s.separated ? (x[0] / b + x[1]) * pow(z, x[2]) : x[0] * pow(z, x[1]);
    case PressureModel::reece:  // Reece 1965: p = (c k'_c + gamma_s b k'_phi) (z / b)^n
      return s.separated ? (x[0] + b * x[1]) * pow(z / b, x[2]) : x[0] * pow(z / b, x[1]);
    case PressureModel::rft:  // Li 2013: sigma_z = zeta alpha_z z
      return x[0] * (rft_plate_alpha() * kPaPerNcm3) * z;
  }
  return T(0);
}

// One residual block per sample: measured force - plate area * pressure at
// the depth below the record's contact depth z0.
// The parameters are fitted in units of their start values (contact depth in
// mm) so that the covariance sees columns of one size.
struct ForceCost {
  Shape shape;
  std::array<double, 3> scale;
  double b, area, depth, force;
  template <class T>
  bool operator()(T const* const* u, T* residual) const {
    std::array<T, 3> x;
    for (int j = 0; j < shape.size(); ++j) x[j] = u[0][j] * scale[j];
    residual[0] = T(force) - T(area) * model_pressure(shape, x.data(), b, T(depth) - u[1][0] * kDepthScale);
    return true;
  }
};

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  return *mid;
}

// Robust force noise: MAD of the second differences / sqrt(6) (a smooth
// loading curve, even a steep rebound, leaves them to the noise).
double force_noise(const std::vector<double>& force) {
  std::vector<double> d(force.size() - 2);
  for (std::size_t i = 2; i < force.size(); ++i) d[i - 2] = force[i] - 2 * force[i - 1] + force[i - 2];
  const double m = median(d);
  for (double& x : d) x = std::abs(x - m);
  return 1.4826 * median(d) / std::sqrt(6.0);
}

// The turning points of depth: the extremes after which it reverses by more than `hysteresis`.
std::vector<std::size_t> depth_turns(const std::vector<double>& depth, double hysteresis) {
  std::vector<std::size_t> turns{0};
  int direction = 0;  // +1 deeper, -1 shallower, 0 not yet moved
  std::size_t extreme = 0, deepest = 0, shallowest = 0;
  for (std::size_t i = 1; i < depth.size(); ++i) {
    if (direction == 0) {
      if (depth[i] > depth[deepest]) deepest = i;
      if (depth[i] < depth[shallowest]) shallowest = i;
      if (depth[i] - depth[0] > hysteresis) {
        direction = 1;
        extreme = deepest;
      } else if (depth[0] - depth[i] > hysteresis) {
        direction = -1;
        extreme = shallowest;
      }
      continue;
    }
    const double beyond = direction * (depth[i] - depth[extreme]);
    if (beyond >= 0) {
      extreme = i;
    } else if (-beyond > hysteresis) {
      turns.push_back(extreme);
      direction = -direction;
      extreme = i;
    }
  }
  turns.push_back(depth.size());
  return turns;
}

void check_record(const PlateRecord& r) {
  if (r.depth.size() != r.force.size()) throw DataError(r.name + ": depth and force have different lengths");
  if (r.depth.size() < 10) throw DataError(r.name + ": fewer than 10 samples");
  if (!(r.plate.width > 0) || (!r.plate.circular && !(r.plate.length > 0))) {
    throw DataError(r.name + ": the plate's size must be positive");
  }
  for (std::size_t i = 0; i < r.depth.size(); ++i) {
    if (!std::isfinite(r.depth[i]) || !std::isfinite(r.force[i])) {
      throw DataError(r.name + ": sample " + std::to_string(i + 1) + " is not a finite number");
    }
  }
}

// The first sample over the threshold that stays over it for three samples.
std::size_t find_contact(const std::vector<double>& force, double threshold) {
  for (std::size_t i = 0; i + 2 < force.size(); ++i) {
    if (force[i] > threshold && force[i + 1] > threshold && force[i + 2] > threshold) return i;
  }
  return force.size();
}

void label_segments(const PlateRecord& r, PlateSegmentation& s) {
  const auto [lo, hi] = std::minmax_element(r.depth.begin(), r.depth.end());
  const std::vector<std::size_t> turns = depth_turns(r.depth, std::max(1e-5, 0.01 * (*hi - *lo)));
  if (s.contact > 0) s.segments.push_back({PlateSegmentKind::approach, 0, s.contact});
  double deepest = -std::numeric_limits<double>::infinity();
  for (std::size_t k = 0; k + 1 < turns.size(); ++k) {
    const std::size_t begin = std::max(turns[k], s.contact), end = turns[k + 1];
    if (begin >= end) continue;
    if (r.depth[end - 1] <= r.depth[begin]) {
      s.segments.push_back({PlateSegmentKind::unloading, begin, end});
      deepest = std::max(deepest, r.depth[begin]);
      continue;
    }
    // Going deeper: reloading up to the deepest point so far, virgin loading past it.
    std::size_t past = begin;
    while (past < end && r.depth[past] <= deepest) ++past;
    if (past > begin) s.segments.push_back({PlateSegmentKind::reloading, begin, past});
    if (past < end) s.segments.push_back({PlateSegmentKind::loading, past, end});
    for (std::size_t i = past; i < end; ++i) {
      if (r.depth[i] > deepest) {
        s.virgin.push_back(i);
        deepest = r.depth[i];
      }
    }
  }
}

}  // namespace

PlateSegmentation segment_plate_record(const PlateRecord& r) {
  check_record(r);
  PlateSegmentation s;
  s.force_noise = force_noise(r.force);
  const double peak = *std::max_element(r.force.begin(), r.force.end());
  s.contact_threshold = 5.0 * s.force_noise;
  s.contact = find_contact(r.force, s.contact_threshold);
  if (s.contact >= r.force.size() || !(peak > 0)) {
    throw DataError(r.name + ": the force never rises above its noise (" + std::to_string(s.force_noise) +
                    " N): no contact");
  }
  s.contact_seen = s.contact > 0;
  label_segments(r, s);
  if (s.virgin.size() < 5) throw DataError(r.name + ": fewer than 5 loading samples after contact");
  return s;
}

double bekker_pressure(double kc, double kphi, double n, double b, double z) {
  const double x[3] = {kc, kphi, n};
  return model_pressure(Shape{PressureModel::bekker, true}, x, b, z);
}
double reece_pressure(double k1, double k2, double n, double b, double z) {
  const double x[3] = {k1, k2, n};
  return model_pressure(Shape{PressureModel::reece, true}, x, b, z);
}
double rft_pressure(double zeta, double z) { return model_pressure(Shape{PressureModel::rft, false}, &zeta, 1.0, z); }

namespace {

// The fit of one relation: start values from log-log regressions, the Ceres
// problem over the fitted samples (optionally leaving a fold out), the
// covariance, the parameters as the caller reads them.
class PressureFit {
 public:
  PressureFit(const std::vector<PlateRecord>& records, const std::vector<PlateSegmentation>& segments, Shape shape)
      : records_(records), segments_(segments), shape_(shape) {}

  // Fits to every virgin sample except fold `left_out` of `folds` (-1: none).
  bool solve(int left_out, int folds, bool with_covariance);
  // Force predicted for sample i of record r with the current parameters.
  double predict(std::size_t r, std::size_t i) const;
  bool in_fold(std::size_t r, std::size_t k, int fold, int folds) const {
    const std::size_t n = segments_[r].virgin.size();
    return static_cast<int>(k * static_cast<std::size_t>(folds) / n) == fold;
  }

  std::vector<double> x;    // model parameters
  std::vector<double> z0;   // contact depth per record
  std::vector<double> cov;  // k x k, scaled by the residual variance
  std::vector<std::pair<double, double>> bounds;
  bool converged = false, covariance_ok = false;
  double chi2 = 0.0;
  std::size_t samples = 0;

 private:
  void start_values();
  void set_bounds();
  void build(ceres::Problem& problem, int left_out, int folds);
  void covariance(ceres::Problem& problem);

  std::array<double, 3> scale_{1.0, 1.0, 1.0};
  std::vector<double> u_, w_;  // scaled parameters and contact depths (mm)

  const std::vector<PlateRecord>& records_;
  const std::vector<PlateSegmentation>& segments_;
  Shape shape_;
};

void PressureFit::start_values() {
  z0.clear();
  for (std::size_t r = 0; r < records_.size(); ++r) {
    const std::size_t c = segments_[r].contact;
    z0.push_back(c > 0 ? records_[r].depth[c - 1] : records_[r].depth[0] - 1e-3);
  }
  // Per record: log p = log k + n log z over its virgin samples.
  std::vector<double> k_eq, n_each, b;
  for (std::size_t r = 0; r < records_.size(); ++r) {
    double sx = 0, sy = 0, sxx = 0, sxy = 0, m = 0;
    for (std::size_t i : segments_[r].virgin) {
      const double z = records_[r].depth[i] - z0[r], p = records_[r].force[i] / records_[r].plate.area();
      if (!(z > 0) || !(p > 0)) continue;
      const double lx = std::log(shape_.model == PressureModel::reece ? z / records_[r].plate.b() : z);
      const double ly = std::log(p);
      sx += lx, sy += ly, sxx += lx * lx, sxy += lx * ly, m += 1;
    }
    const double slope = m > 2 && sxx * m - sx * sx > 0 ? (m * sxy - sx * sy) / (m * sxx - sx * sx) : 1.0;
    n_each.push_back(std::clamp(slope, 0.2, 2.5));
    k_eq.push_back(m > 0 ? std::exp((sy - n_each.back() * sx) / m) : 1e5);
    b.push_back(records_[r].plate.b());
  }
  const double n = std::accumulate(n_each.begin(), n_each.end(), 0.0) / static_cast<double>(n_each.size());
  if (shape_.model == PressureModel::rft) {
    x = {k_eq[0] / (rft_plate_alpha() * kPaPerNcm3)};
    return;
  }
  if (!shape_.separated) {
    x = {k_eq[0], n};
    return;
  }
  // k_eq = kc / b + kphi (Bekker) or k1 + b k2 (Reece): a line through the sizes.
  std::vector<double> u(b.size());
  for (std::size_t i = 0; i < b.size(); ++i) u[i] = shape_.model == PressureModel::bekker ? 1.0 / b[i] : b[i];
  const double mu = std::accumulate(u.begin(), u.end(), 0.0) / static_cast<double>(u.size());
  const double mk = std::accumulate(k_eq.begin(), k_eq.end(), 0.0) / static_cast<double>(k_eq.size());
  double suu = 0, suk = 0;
  for (std::size_t i = 0; i < u.size(); ++i) suu += (u[i] - mu) * (u[i] - mu), suk += (u[i] - mu) * (k_eq[i] - mk);
  const double slope = suu > 0 ? suk / suu : 0.0;
  x = shape_.model == PressureModel::bekker ? std::vector<double>{slope, mk - slope * mu, n}
                                            : std::vector<double>{mk - slope * mu, slope, n};
}

void PressureFit::set_bounds() {
  const double big = 1e12;
  switch (shape_.model) {
    case PressureModel::bekker:
      bounds = shape_.separated ? std::vector<std::pair<double, double>>{{-1e9, 1e9}, {-big, big}, {0.05, 3.0}}
                                : std::vector<std::pair<double, double>>{{0.0, big}, {0.05, 3.0}};
      break;
    case PressureModel::reece:
      bounds = shape_.separated ? std::vector<std::pair<double, double>>{{-big, big}, {-big, big}, {0.05, 3.0}}
                                : std::vector<std::pair<double, double>>{{0.0, big}, {0.05, 3.0}};
      break;
    case PressureModel::rft:
      bounds = {{0.0, 1e3}};
      break;
  }
}

double PressureFit::predict(std::size_t r, std::size_t i) const {
  const PlateRecord& rec = records_[r];
  return rec.plate.area() * model_pressure(shape_, x.data(), rec.plate.b(), rec.depth[i] - z0[r]);
}

// Residual blocks of the fitted samples and the bounds, over the scaled
// parameters u (model) and w (contact depths, mm).
void PressureFit::build(ceres::Problem& problem, int left_out, int folds) {
  samples = 0;
  for (std::size_t r = 0; r < records_.size(); ++r) {
    const PlateRecord& rec = records_[r];
    const auto& virgin = segments_[r].virgin;
    for (std::size_t k = 0; k < virgin.size(); ++k) {
      if (left_out >= 0 && in_fold(r, k, left_out, folds)) continue;
      auto* cost = new ceres::DynamicAutoDiffCostFunction<ForceCost, 4>(
          new ForceCost{shape_, scale_, rec.plate.b(), rec.plate.area(), rec.depth[virgin[k]], rec.force[virgin[k]]});
      cost->AddParameterBlock(shape_.size());
      cost->AddParameterBlock(1);
      cost->SetNumResiduals(1);
      problem.AddResidualBlock(cost, nullptr, u_.data(), &w_[r]);
      ++samples;
    }
    // The contact lies before the first sample over the threshold (before
    // the record, by at most its depth range, when it starts in contact).
    const auto& depth = rec.depth;
    const std::size_t c = segments_[r].contact;
    const auto [shallowest, deepest] = std::minmax_element(depth.begin(), depth.end());
    const double upper = depth[c] / kDepthScale;
    const double lower =
        (c > 0 ? std::min(depth.front(), depth[c]) - 1e-9 : depth.front() - (*deepest - *shallowest)) / kDepthScale;
    w_[r] = std::clamp(w_[r], lower, upper);
    problem.SetParameterLowerBound(&w_[r], 0, lower);
    problem.SetParameterUpperBound(&w_[r], 0, upper);
  }
  for (std::size_t j = 0; j < u_.size(); ++j) {
    const double lo = bounds[j].first / scale_[j], hi = bounds[j].second / scale_[j];
    u_[j] = std::clamp(u_[j], lo, hi);
    problem.SetParameterLowerBound(u_.data(), static_cast<int>(j), lo);
    problem.SetParameterUpperBound(u_.data(), static_cast<int>(j), hi);
  }
}

// The model parameters' covariance, in their units, scaled by the residual
// variance (unit weights: the force noise is the residual scatter).
void PressureFit::covariance(ceres::Problem& problem) {
  ceres::Covariance::Options co;
  co.algorithm_type = ceres::DENSE_SVD;
  co.null_space_rank = 0;
  ceres::Covariance c(co);
  const std::size_t k = u_.size();
  cov.assign(k * k, NAN);
  std::vector<std::pair<const double*, const double*>> blocks{{u_.data(), u_.data()}};
  covariance_ok = c.Compute(blocks, &problem) && c.GetCovarianceBlock(u_.data(), u_.data(), cov.data());
  const double dof = static_cast<double>(samples) - static_cast<double>(k + records_.size());
  for (std::size_t i = 0; i < k; ++i) {
    for (std::size_t j = 0; j < k; ++j) cov[i * k + j] *= scale_[i] * scale_[j] * (dof > 0 ? chi2 / dof : NAN);
  }
}

bool PressureFit::solve(int left_out, int folds, bool with_covariance) {
  start_values();
  set_bounds();
  scale_ = {1.0, 1.0, 1.0};
  u_.assign(x.size(), 0.0);
  for (std::size_t j = 0; j < x.size(); ++j) {
    scale_[j] = std::abs(x[j]) > 0 ? std::abs(x[j]) : 1.0;
    u_[j] = x[j] / scale_[j];
  }
  w_.resize(z0.size());
  for (std::size_t r = 0; r < z0.size(); ++r) w_[r] = z0[r] / kDepthScale;
  ceres::Problem problem;
  build(problem, left_out, folds);
  ceres::Solver::Options so;
  so.linear_solver_type = ceres::DENSE_QR;
  so.max_num_iterations = 200;
  so.function_tolerance = so.parameter_tolerance = 1e-12;
  ceres::Solver::Summary summary;
  ceres::Solve(so, &problem, &summary);
  converged = summary.IsSolutionUsable() && summary.termination_type == ceres::CONVERGENCE;
  chi2 = 2.0 * summary.final_cost;
  for (std::size_t j = 0; j < x.size(); ++j) x[j] = u_[j] * scale_[j];
  for (std::size_t r = 0; r < z0.size(); ++r) z0[r] = w_[r] * kDepthScale;
  covariance_ok = false;
  if (with_covariance) covariance(problem);
  return converged;
}

// Names and units of the parameters as fitted, and the derived Reece moduli.
void describe(const Shape& s, const PressureFit& f, const PlateFitOptions& o, PressureSinkageFit& out) {
  std::vector<std::pair<const char*, const char*>> names;
  if (s.model == PressureModel::bekker) {
    names = s.separated ? decltype(names){{"kc", "Pa/m^(n-1)"}, {"kphi", "Pa/m^n"}, {"n", "1"}}
                        : decltype(names){{"k_eq", "Pa/m^n"}, {"n", "1"}};
  } else if (s.model == PressureModel::reece) {
    names = s.separated ? decltype(names){{"c_kc_prime", "Pa"}, {"gamma_kphi_prime", "N/m^3"}, {"n", "1"}}
                        : decltype(names){{"k_eq", "Pa"}, {"n", "1"}};
  } else {
    names = {{"zeta", "1"}};
  }
  for (std::size_t j = 0; j < names.size(); ++j) {
    PlateParameter p{names[j].first, names[j].second, f.x[j], NAN, false};
    const double span = f.bounds[j].second - f.bounds[j].first;
    p.at_bound = f.x[j] <= f.bounds[j].first + 1e-9 * span || f.x[j] >= f.bounds[j].second - 1e-9 * span;
    if (f.covariance_ok && !p.at_bound) p.sigma = std::sqrt(std::max(f.cov[j * names.size() + j], 0.0));
    out.parameters.push_back(p);
  }
  if (s.model == PressureModel::reece && s.separated) {
    const PlateParameter a = out.parameters[0], g = out.parameters[1];
    if (o.cohesion > 0) out.parameters.push_back({"kc_prime", "1", a.value / o.cohesion, a.sigma / o.cohesion});
    if (o.unit_weight > 0) {
      out.parameters.push_back({"kphi_prime", "1", g.value / o.unit_weight, g.sigma / o.unit_weight});
    }
  }
}

PressureSinkageFit fit_relation(const std::vector<PlateRecord>& records, const std::vector<PlateSegmentation>& segs,
                                Shape shape, const PlateFitOptions& options) {
  PressureSinkageFit out;
  out.model = shape.model;
  out.sizes_separated = shape.separated;
  PressureFit fit(records, segs, shape);
  fit.solve(-1, options.folds, true);
  out.converged = fit.converged;
  out.covariance_ok = fit.covariance_ok;
  out.samples = fit.samples;
  out.contact_depths = fit.z0;
  out.rmse_N = std::sqrt(fit.chi2 / static_cast<double>(std::max<std::size_t>(fit.samples, 1)));
  describe(shape, fit, options, out);
  // Held out: each contiguous depth fold of every record, predicted by a fit without it.
  double sum = 0;
  std::size_t count = 0;
  for (int fold = 0; fold < options.folds; ++fold) {
    PressureFit part(records, segs, shape);
    part.solve(fold, options.folds, false);
    for (std::size_t r = 0; r < records.size(); ++r) {
      for (std::size_t k = 0; k < segs[r].virgin.size(); ++k) {
        if (!part.in_fold(r, k, fold, options.folds)) continue;
        const double e = records[r].force[segs[r].virgin[k]] - part.predict(r, segs[r].virgin[k]);
        sum += e * e, ++count;
      }
    }
  }
  out.held_out_rmse_N = count > 0 ? std::sqrt(sum / static_cast<double>(count)) : NAN;
  if (!shape.separated && shape.model != PressureModel::rft) {
    out.note = shape.model == PressureModel::bekker
                   ? "one plate size: k_c and k_phi cannot be told apart; k_eq = k_c / b + k_phi holds for this b only"
                   : "one plate size: k'_c and k'_phi cannot be told apart; k_eq = c k'_c + gamma b k'_phi holds for "
                     "this b only";
  }
  return out;
}

}  // namespace

double fitted_force(const PressureSinkageFit& fit, const Plate& plate, double contact_depth, double depth) {
  const Shape shape{fit.model, fit.sizes_separated};
  std::array<double, 3> x{};
  if (fit.parameters.size() < static_cast<std::size_t>(shape.size())) return NAN;
  for (int j = 0; j < shape.size(); ++j)
    x[static_cast<std::size_t>(j)] = fit.parameters[static_cast<std::size_t>(j)].value;
  return plate.area() * model_pressure(shape, x.data(), plate.b(), depth - contact_depth);
}

PlateAnalysis analyse_plate_tests(const std::vector<PlateRecord>& records, const PlateFitOptions& options) {
  if (records.empty()) throw DataError("no plate test to fit");
  PlateAnalysis a;
  std::set<double> sizes;
  for (const auto& r : records) {
    a.records.push_back(segment_plate_record(r));
    sizes.insert(r.plate.b());
  }
  // Sizes closer than 1 % are one size.
  for (double b : sizes) {
    if (a.plate_sizes.empty() || b > 1.01 * a.plate_sizes.back()) a.plate_sizes.push_back(b);
  }
  const bool separated = a.plate_sizes.size() >= 2;
  for (PressureModel m : {PressureModel::bekker, PressureModel::reece, PressureModel::rft}) {
    a.fits.push_back(fit_relation(records, a.records, Shape{m, separated}, options));
  }
  return a;
}

}  // namespace roverlab::terramechanics
