#include "core/terramechanics/soil_identification.h"

#include <ceres/ceres.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <memory>

#include "core/common/error.h"
#include "core/common/thread_pool.h"
#include "core/terramechanics/model_impl.h"
#include "core/terramechanics/slip_angle_model.h"

namespace roverlab::terramechanics {

const char* to_string(Quantity q) {
  switch (q) {
    case Quantity::drawbar_pull:
      return "drawbar_pull";
    case Quantity::torque:
      return "torque";
    case Quantity::sinkage:
      return "sinkage";
    case Quantity::lateral_force:
      return "lateral_force";
  }
  return "?";
}

const char* unit_of(Quantity q) {
  switch (q) {
    case Quantity::drawbar_pull:
      return "N";
    case Quantity::torque:
      return "N*m";
    case Quantity::sinkage:
      return "m";
    case Quantity::lateral_force:
      return "N";
  }
  return "?";
}

namespace {
struct ParameterName {
  Parameter p;
  const char* name;
  Bounds bounds;
};
const ParameterName kParameters[] = {
    {Parameter::n, "n", {0.2, 2.5}},
    {Parameter::cohesion, "cohesion", {0.0, 20000.0}},
    {Parameter::friction_angle, "friction_angle", {0.05, 1.2}},
    {Parameter::shear_modulus, "shear_modulus", {1e-4, 0.2}},
    {Parameter::kc, "kc", {-1e6, 1e7}},
    {Parameter::kphi, "kphi", {1e3, 1e9}},
    {Parameter::c1, "c1", {0.0, 1.0}},
    {Parameter::c2, "c2", {-0.5, 1.0}},
    {Parameter::slip_sinkage_n1, "slip_sinkage_n1", {-0.5, 2.0}},
    {Parameter::grouser_effectiveness, "grouser_effectiveness", {0.0, 2.0}},
    {Parameter::bulldozing_scale, "bulldozing_scale", {0.0, 10.0}},
    {Parameter::soil_strength, "soil_strength", {0.1, 5.0}},
    {Parameter::shear_modulus_slip, "shear_modulus_slip", {-0.9, 20.0}},
    {Parameter::rear_angle_ratio, "rear_angle_ratio", {0.0, 1.0}},
    {Parameter::lateral_shear_modulus, "lateral_shear_modulus", {1e-4, 0.2}},
    {Parameter::sidewall_scale, "sidewall_scale", {0.0, 20.0}},
    // The peaked shear curve: residual over maximum stress in (0, 1], and the
    // maximum's displacement with the range of K_s.
    {Parameter::shear_residual_ratio, "shear_residual_ratio", {0.01, 1.0}},
    {Parameter::shear_peak_displacement, "shear_peak_displacement", {1e-4, 0.2}},
    // RFT (rft.h): zeta in N/m^3 (0.01 to 100 N/cm^3), the pile-up fraction and the depth-dependent scale.
    {Parameter::rft_scale, "rft_scale", {1e4, 1e8}},
    // Pile-up up to 10 sinkages: dragged sideways, a wheel meets |F_y| of 2-2.5 W (issue 43), which needs 2-3 here.
    {Parameter::rft_pileup, "rft_pileup", {0.0, 10.0}},
    {Parameter::rft_depth_scale, "rft_depth_scale", {-0.9, 20.0}},
};

// Assigns one free parameter inside the model's parameter set.
template <typename T>
void assign(detail::Params<T>& p, Parameter which, const T& v) {
  using std::tan;
  switch (which) {
    case Parameter::n:
      p.n = v;
      break;
    case Parameter::cohesion:
      p.cohesion = v;
      break;
    case Parameter::friction_angle:
      p.tan_phi = tan(v);
      break;
    case Parameter::shear_modulus:
      p.shear_modulus = v;
      break;
    case Parameter::kc:
      p.kc = v;
      break;
    case Parameter::kphi:
      p.kphi = v;
      break;
    case Parameter::c1:
      p.c1 = v;
      break;
    case Parameter::c2:
      p.c2 = v;
      break;
    case Parameter::slip_sinkage_n1:
      p.slip_sinkage_n1 = v;
      break;
    case Parameter::grouser_effectiveness:
      p.grouser_effectiveness = v;
      break;
    case Parameter::bulldozing_scale:
      p.bulldozing_scale = v;
      break;
    case Parameter::soil_strength:
      p.soil_strength = v;
      break;
    case Parameter::shear_modulus_slip:
      p.shear_modulus_slip = v;
      break;
    case Parameter::rear_angle_ratio:
      p.rear_angle_ratio = v;
      break;
    case Parameter::shear_residual_ratio:
      p.shear_residual_ratio = v;
      break;
    case Parameter::shear_peak_displacement:
      p.shear_peak_displacement = v;
      break;
    case Parameter::lateral_shear_modulus:  // the slip-angle model only (SlipAnglePointCost)
    case Parameter::sidewall_scale:
    case Parameter::rft_scale:  // RFT only (SlipAnglePointCost)
    case Parameter::rft_pileup:
    case Parameter::rft_depth_scale:
      break;
  }
}

// Residuals of one measured point: one per measured quantity, each in sigmas.
struct PointCost {
  const Soil* soil;
  const ModelOptions* model;
  const WheelTestPoint* point;
  const std::vector<Parameter>* free;
  MeasurementSigma sigma;
  // The point's last entry angles, where its next solves start (model.h): see
  // SlipAnglePointCost::hint.
  mutable EntryAngleHint hint;

  template <typename T>
  bool operator()(T const* const* x, T* residual) const {
    detail::Params<T> p = detail::make_params<T>(*soil, model->extensions);
    for (std::size_t k = 0; k < free->size(); ++k) assign(p, (*free)[k], x[0][k]);
    const auto sol = detail::solve_any_slip(p, point->wheel, *model, point->slip, point->load, &hint);
    if (sol.status != TractionStatus::ok) return false;
    int r = 0;
    for (Quantity q : kQuantities) {
      const auto m = point->measured(q);
      if (!m || q == Quantity::lateral_force) continue;  // straight driving: no lateral force
      const T& predicted = q == Quantity::drawbar_pull ? sol.drawbar : q == Quantity::torque ? sol.torque : sol.sinkage;
      residual[r++] = (predicted - *m) / sigma.of(q);
    }
    return true;
  }
};

// The slip-angle model's values of the four quantities (NaN: not carried).
std::array<double, 4> predict(const Soil& soil, const ModelOptions& model, const WheelTestPoint& point,
                              EntryAngleHint* hint = nullptr) {
  std::array<double, 4> out{NAN, NAN, NAN, NAN};
  if (!has_lateral_force(model.kind)) {
    const Traction t = evaluate(soil, point.wheel, point.load, point.slip, model);
    if (t.ok()) out = {t.drawbar_pull, t.resistive_torque, t.sinkage, NAN};
    return out;
  }
  const SlipAngleTraction t =
      evaluate_slip_angle(soil, point.wheel, point.load, point.slip, point.slip_angle, model, {}, hint);
  if (t.ok()) out = {t.drawbar_pull, t.resistive_torque, t.sinkage, t.lateral_force};
  return out;
}

// The same residuals through the slip-angle model (Ishigami et al. 2007),
// which is written for doubles: its derivatives by central differences.
struct SlipAnglePointCost {
  const Soil* soil;
  const ModelOptions* model;
  const WheelTestPoint* point;
  const std::vector<Parameter>* free;
  MeasurementSigma sigma;
  // The point's last entry angles, where its next solves start (model.h).
  // A point is evaluated by one thread at a time, in the order of Ceres'
  // evaluations (PointEvaluations), so its hints, and the results, do not
  // depend on the threads.
  mutable EntryAngleHint hint;

  bool operator()(double const* const* x, double* residual) const {
    Soil s = *soil;
    ModelOptions m = *model;
    // A central difference at a bound steps past it, where the model may not
    // exist (a pile-up or a grouser scale below 0): the model there is the
    // one at the bound (a one-sided slope, half as steep, in the right
    // direction), instead of a failed evaluation that ends the fit.
    for (std::size_t k = 0; k < free->size(); ++k) {
      const Bounds b = default_bounds((*free)[k]);
      set_parameter(s, m.extensions, (*free)[k], std::clamp(x[0][k], b.lower, b.upper));
    }
    const auto predicted = predict(s, m, *point, &hint);
    int r = 0;
    for (Quantity q : kQuantities) {
      const auto measured = point->measured(q);
      if (!measured) continue;
      const double v = predicted[static_cast<std::size_t>(q)];
      if (!std::isfinite(v)) return false;
      residual[r++] = (v - *measured) / sigma.of(q);
    }
    return true;
  }
};

int measured_count(const WheelTestPoint& p, const ModelOptions& model) {
  int n = 0;
  for (Quantity q : kQuantities) {
    n += p.measured(q) && (q != Quantity::lateral_force || has_lateral_force(model.kind)) ? 1 : 0;
  }
  return n;
}

}  // namespace

const char* to_string(Parameter p) {
  for (const auto& row : kParameters) {
    if (row.p == p) return row.name;
  }
  return "?";
}

Parameter parse_parameter(const std::string& text) {
  for (const auto& row : kParameters) {
    if (text == row.name) return row.p;
  }
  std::string known;
  for (const auto& row : kParameters) known += std::string(known.empty() ? "" : ", ") + row.name;
  throw DataError("unknown parameter '" + text + "' (" + known + ")");
}

Bounds default_bounds(Parameter p) {
  for (const auto& row : kParameters) {
    if (row.p == p) return row.bounds;
  }
  return {-std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity()};
}

double get_parameter(const Soil& s, const Extensions& e, Parameter p) {
  switch (p) {
    case Parameter::n:
      return s.n;
    case Parameter::cohesion:
      return s.cohesion;
    case Parameter::friction_angle:
      return s.friction_angle;
    case Parameter::shear_modulus:
      return s.shear_modulus;
    case Parameter::kc:
      return s.kc;
    case Parameter::kphi:
      return s.kphi;
    case Parameter::c1:
      return s.c1;
    case Parameter::c2:
      return s.c2;
    case Parameter::slip_sinkage_n1:
      return e.slip_sinkage_n1;
    case Parameter::grouser_effectiveness:
      return e.grouser_effectiveness;
    case Parameter::bulldozing_scale:
      return e.bulldozing_scale;
    case Parameter::soil_strength:
      return e.soil_strength;
    case Parameter::shear_modulus_slip:
      return e.shear_modulus_slip;
    case Parameter::rear_angle_ratio:
      return e.rear_angle_ratio;
    case Parameter::lateral_shear_modulus:
      return lateral_shear_modulus(s);
    case Parameter::sidewall_scale:
      return e.sidewall_scale;
    case Parameter::shear_residual_ratio:
      return e.shear_residual_ratio;
    case Parameter::shear_peak_displacement:
      return e.shear_peak_displacement;
    case Parameter::rft_scale:
      return s.rft_scale;
    case Parameter::rft_pileup:
      return e.rft_pileup;
    case Parameter::rft_depth_scale:
      return e.rft_depth_scale;
  }
  return NAN;
}

void set_parameter(Soil& s, Extensions& e, Parameter p, double v) {
  switch (p) {
    case Parameter::n:
      s.n = v;
      break;
    case Parameter::cohesion:
      s.cohesion = v;
      break;
    case Parameter::friction_angle:
      s.friction_angle = v;
      break;
    case Parameter::shear_modulus:
      s.shear_modulus = v;
      break;
    case Parameter::kc:
      s.kc = v;
      break;
    case Parameter::kphi:
      s.kphi = v;
      break;
    case Parameter::c1:
      s.c1 = v;
      break;
    case Parameter::c2:
      s.c2 = v;
      break;
    case Parameter::slip_sinkage_n1:
      e.slip_sinkage_n1 = v;
      break;
    case Parameter::grouser_effectiveness:
      e.grouser_effectiveness = v;
      break;
    case Parameter::bulldozing_scale:
      e.bulldozing_scale = v;
      break;
    case Parameter::soil_strength:
      e.soil_strength = v;
      break;
    case Parameter::shear_modulus_slip:
      e.shear_modulus_slip = v;
      break;
    case Parameter::rear_angle_ratio:
      e.rear_angle_ratio = v;
      break;
    case Parameter::lateral_shear_modulus:
      s.lateral_shear_modulus = v;
      break;
    case Parameter::sidewall_scale:
      e.sidewall_scale = v;
      break;
    case Parameter::shear_residual_ratio:
      e.shear_residual_ratio = v;
      break;
    case Parameter::shear_peak_displacement:
      e.shear_peak_displacement = v;
      break;
    case Parameter::rft_scale:
      s.rft_scale = v;
      break;
    case Parameter::rft_pileup:
      e.rft_pileup = v;
      break;
    case Parameter::rft_depth_scale:
      e.rft_depth_scale = v;
      break;
  }
}

namespace {

// Whether the residuals and their Jacobian at the solution are finite: Ceres's
// covariance (its dense SVD) is undefined on a NaN or infinite Jacobian and has
// crashed on one (a constant negative load, a load of 1e300 N).
bool finite_jacobian(ceres::Problem& problem) {
  double cost = 0;
  std::vector<double> residuals;
  ceres::CRSMatrix jacobian;
  if (!problem.Evaluate(ceres::Problem::EvaluateOptions(), &cost, &residuals, nullptr, &jacobian)) return false;
  const auto finite = [](double v) { return std::isfinite(v); };
  return std::isfinite(cost) && std::all_of(residuals.begin(), residuals.end(), finite) &&
         std::all_of(jacobian.values.begin(), jacobian.values.end(), finite);
}

}  // namespace

namespace {

// Every point's residuals (and Jacobian) computed before Ceres asks for
// them, in chunks on the shared thread pool (core/common/thread_pool.h),
// from Ceres' evaluation callback; each point's block then copies its own
// (the callback's documented use). A point is computed by its own cost
// function, called as Ceres would call it, and Ceres sums the blocks in
// their order: a fit is the same on any number of threads.
class PointEvaluations : public ceres::EvaluationCallback {
 public:
  PointEvaluations(const double* x, std::size_t k) : x_(x), at_(k) {}
  // Point j's cost function (m residuals); returns j.
  std::size_t add(std::unique_ptr<ceres::CostFunction> cost, int m) {
    const auto rows = static_cast<std::size_t>(m);
    points_.push_back(Point{std::move(cost), std::vector<double>(rows), std::vector<double>(rows * at_.size())});
    return points_.size() - 1;
  }
  void PrepareForEvaluation(bool evaluate_jacobians, bool /*new_evaluation_point*/) override {
    std::copy(x_, x_ + at_.size(), at_.begin());
    const std::size_t chunks = (points_.size() + kChunk - 1) / kChunk;
    shared_thread_pool().for_each_index(chunks, [&](std::size_t c) {
      for (std::size_t j = c * kChunk; j < std::min(points_.size(), (c + 1) * kChunk); ++j) {
        Point& p = points_[j];
        const double* parameters[1] = {at_.data()};
        double* jacobian[1] = {p.jacobian.data()};
        p.ok = p.cost->Evaluate(parameters, p.residuals.data(), evaluate_jacobians ? jacobian : nullptr);
        p.has_jacobian = evaluate_jacobians;
      }
    });
  }
  // Point j at x: what PrepareForEvaluation computed, or (asked at another
  // point, or for a Jacobian it did not compute) its cost function's answer.
  bool evaluate(std::size_t j, double const* const* x, double* residuals, double** jacobians) const {
    const Point& p = points_[j];
    const bool wants_jacobian = jacobians != nullptr && jacobians[0] != nullptr;
    if (!std::equal(at_.begin(), at_.end(), x[0]) || (wants_jacobian && !p.has_jacobian))
      return p.cost->Evaluate(x, residuals, jacobians);
    if (!p.ok) return false;
    std::copy(p.residuals.begin(), p.residuals.end(), residuals);
    if (wants_jacobian) std::copy(p.jacobian.begin(), p.jacobian.end(), jacobians[0]);
    return true;
  }

 private:
  static constexpr std::size_t kChunk = 16;  // points a task
  struct Point {
    std::unique_ptr<ceres::CostFunction> cost;
    std::vector<double> residuals, jacobian;  // jacobian: m x k, row-major (Ceres' layout)
    bool ok = false, has_jacobian = false;
  };
  const double* x_;         // the parameters Ceres evaluates at (the user's block)
  std::vector<double> at_;  // ... as they were when PrepareForEvaluation ran
  std::vector<Point> points_;
};

// A point's residual block: what PointEvaluations computed for it.
class EvaluatedPoint : public ceres::CostFunction {
 public:
  EvaluatedPoint(const PointEvaluations* all, std::size_t j, int m, int k) : all_(all), j_(j) {
    set_num_residuals(m);
    mutable_parameter_block_sizes()->push_back(k);
  }
  bool Evaluate(double const* const* x, double* residuals, double** jacobians) const override {
    return all_->evaluate(j_, x, residuals, jacobians);
  }

 private:
  const PointEvaluations* all_;
  std::size_t j_;
};

// One residual block per point with a measured quantity (Ceres's examples),
// each evaluated through `evaluations` (the problem's evaluation callback).
void add_point_residuals(ceres::Problem& problem, PointEvaluations& evaluations, const Soil& soil,
                         const std::vector<WheelTestPoint>& points, const IdentificationOptions& options,
                         std::vector<double>& x) {
  const std::size_t k = options.free.size();
  for (const auto& point : points) {
    const int m = measured_count(point, options.model);
    if (m == 0) continue;
    std::unique_ptr<ceres::DynamicCostFunction> cost;
    if (has_lateral_force(options.model.kind)) {
      cost = std::make_unique<ceres::DynamicNumericDiffCostFunction<SlipAnglePointCost, ceres::CENTRAL>>(
          new SlipAnglePointCost{&soil, &options.model, &point, &options.free, options.sigma, {}});
    } else {
      // Stride 8: a fit of up to 8 parameters differentiates each point in one pass (one sinkage solve).
      cost = std::make_unique<ceres::DynamicAutoDiffCostFunction<PointCost, 8>>(
          new PointCost{&soil, &options.model, &point, &options.free, options.sigma, {}});
    }
    cost->AddParameterBlock(static_cast<int>(k));
    cost->SetNumResiduals(m);
    const std::size_t j = evaluations.add(std::move(cost), m);
    ceres::LossFunction* loss = options.huber_sigmas > 0.0 ? new ceres::HuberLoss(options.huber_sigmas) : nullptr;
    problem.AddResidualBlock(new EvaluatedPoint(&evaluations, j, m, static_cast<int>(k)), loss, x.data());
  }
  if (problem.NumResidualBlocks() == 0) throw DataError("no measured quantities to fit");
  for (std::size_t i = 0; i < k; ++i) {
    const Bounds b = default_bounds(options.free[i]);
    problem.SetParameterLowerBound(x.data(), static_cast<int>(i), b.lower);
    problem.SetParameterUpperBound(x.data(), static_cast<int>(i), b.upper);
  }
}

// The free parameters' covariance (k x k, row-major; NaN where Ceres cannot
// give it), result.covariance_ok saying whether it could.
std::vector<double> parameter_covariance(ceres::Problem& problem, std::vector<double>& x,
                                         const IdentificationOptions& options, IdentificationResult& result) {
  const std::size_t k = options.free.size();
  std::vector<double> cov(k * k, NAN);
  if (options.covariance && finite_jacobian(problem)) {
    ceres::Covariance::Options co;
    co.algorithm_type = ceres::DENSE_SVD;
    co.null_space_rank = 0;
    ceres::Covariance covariance(co);
    std::vector<std::pair<const double*, const double*>> blocks{{x.data(), x.data()}};
    result.covariance_ok =
        covariance.Compute(blocks, &problem) && covariance.GetCovarianceBlock(x.data(), x.data(), cov.data());
  }
  return cov;
}

// Solves for the free parameters within their bounds and records them, with
// their sigmas and correlations, in result.
void fit_free_parameters(const Soil& soil, const std::vector<WheelTestPoint>& points,
                         const IdentificationOptions& options, IdentificationResult& result) {
  const std::size_t k = options.free.size();
  std::vector<double> x(k);
  for (std::size_t i = 0; i < k; ++i) x[i] = get_parameter(soil, result.extensions, options.free[i]);
  PointEvaluations evaluations(x.data(), k);
  ceres::Problem::Options po;
  po.evaluation_callback = &evaluations;
  ceres::Problem problem(po);
  add_point_residuals(problem, evaluations, soil, points, options, x);
  ceres::Solver::Options so;
  so.linear_solver_type = ceres::DENSE_QR;
  so.max_num_iterations = options.max_iterations;
  so.function_tolerance = options.tolerance;
  so.parameter_tolerance = options.tolerance;
  // A step projected onto the bounds is searched along by the cost alone:
  // Ceres' default (cubic) interpolation takes the gradient at every trial
  // step, a whole Jacobian (2k + 1 evaluations of every point by numeric
  // differences) each time.
  so.line_search_interpolation_type = ceres::QUADRATIC;
  so.logging_type = ceres::SILENT;
  so.minimizer_progress_to_stdout = false;
  ceres::Solver::Summary summary;
  ceres::Solve(so, &problem, &summary);
  result.converged = summary.termination_type == ceres::CONVERGENCE;
  result.message = summary.message;

  const std::vector<double> cov = parameter_covariance(problem, x, options, result);
  for (std::size_t i = 0; i < k; ++i) {
    EstimatedParameter e;
    e.parameter = options.free[i];
    e.value = x[i];
    e.bounds = default_bounds(options.free[i]);
    const double span = e.bounds.upper - e.bounds.lower;
    e.at_bound = x[i] <= e.bounds.lower + 1e-9 * span || x[i] >= e.bounds.upper - 1e-9 * span;
    e.sigma = result.covariance_ok ? std::sqrt(std::max(cov[i * k + i], 0.0)) : NAN;
    result.parameters.push_back(e);
    set_parameter(result.soil, result.extensions, options.free[i], x[i]);
  }
  if (result.covariance_ok) {
    result.correlation.assign(k * k, NAN);
    for (std::size_t i = 0; i < k; ++i) {
      for (std::size_t j = 0; j < k; ++j) {
        const double d = std::sqrt(cov[i * k + i] * cov[j * k + j]);
        result.correlation[i * k + j] = d > 0.0 ? cov[i * k + j] / d : NAN;
      }
    }
  }
}

// Every measured quantity's residual under the fitted model, their chi^2;
// scatter larger than the claimed sigmas widens the parameter sigmas.
void score_points(const std::vector<WheelTestPoint>& points, const IdentificationOptions& options,
                  IdentificationResult& result) {
  ModelOptions fitted = options.model;
  fitted.extensions = result.extensions;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const auto predicted = predict(result.soil, fitted, points[i]);
    for (Quantity q : kQuantities) {
      const auto m = points[i].measured(q);
      if (!m || (q == Quantity::lateral_force && !has_lateral_force(fitted.kind))) continue;
      PointResidual r;
      r.point = i;
      r.quantity = q;
      r.measured = *m;
      r.sigma = options.sigma.of(q);
      r.predicted = predicted[static_cast<std::size_t>(q)];
      const double z = (r.predicted - r.measured) / r.sigma;
      result.chi2 += std::isfinite(z) ? z * z : 0.0;
      ++result.measurements;
      result.residuals.push_back(r);
    }
  }
  const std::size_t k = options.free.size();
  if (result.measurements > k && k > 0) {
    const double reduced = result.chi2 / static_cast<double>(result.measurements - k);
    if (reduced > 1.0) {
      for (auto& e : result.parameters) e.sigma *= std::sqrt(reduced);
    }
  }
}

}  // namespace

IdentificationResult identify_soil(const Soil& soil, const std::vector<WheelTestPoint>& points,
                                   const IdentificationOptions& options) {
  IdentificationResult result;
  result.soil = soil;
  result.extensions = options.model.extensions;
  if (options.free.empty()) {
    result.converged = true;
    result.covariance_ok = true;
  } else {
    fit_free_parameters(soil, points, options, result);
  }
  score_points(points, options, result);
  return result;
}

}  // namespace roverlab::terramechanics
