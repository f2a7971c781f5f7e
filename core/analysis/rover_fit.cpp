#include "core/analysis/rover_fit.h"

#include <ceres/ceres.h>

#include <algorithm>
#include <cmath>

#include <Eigen/Dense>

namespace roverlab::analysis::rover {

namespace {

// The fit blocks' residuals as a function of the free parameters; the
// Jacobian by forward differences (backward at an upper bound).
class SimulationCost final : public ceres::CostFunction {
 public:
  SimulationCost(Predictor& predictor, std::vector<FitParameter>& parameters, std::vector<std::size_t> free)
      : predictor_(predictor), parameters_(parameters), free_(std::move(free)) {
    set_num_residuals(static_cast<int>(predictor.count(Part::fit)));
    mutable_parameter_block_sizes()->push_back(static_cast<int>(free_.size()));
  }
  bool Evaluate(double const* const* x, double* residuals, double** jacobians) const override {
    std::vector<FitParameter> p = parameters_;
    for (std::size_t j = 0; j < free_.size(); ++j) p[free_[j]].value = x[0][j];
    const std::vector<double> r = predictor_.residuals(effects_of(predictor_.scenario_effects(), p), Part::fit);
    std::copy(r.begin(), r.end(), residuals);
    if (jacobians == nullptr || jacobians[0] == nullptr) return true;
    const std::size_t n = r.size(), m = free_.size();
    last_x_.assign(x[0], x[0] + m);
    for (std::size_t j = 0; j < m; ++j) {
      FitParameter& q = p[free_[j]];
      const double v = q.value;
      const double h = v + q.spec.step <= q.spec.upper ? q.spec.step : -q.spec.step;
      q.value = v + h;
      const std::vector<double> r2 = predictor_.residuals(effects_of(predictor_.scenario_effects(), p), Part::fit);
      q.value = v;
      for (std::size_t i = 0; i < n; ++i) jacobians[0][i * m + j] = (r2[i] - r[i]) / h;
    }
    last_jacobian_.assign(jacobians[0], jacobians[0] + n * m);
    return true;
  }
  // The last Jacobian computed, when it was computed at x (saves a simulation per parameter).
  const std::vector<double>* jacobian_at(const std::vector<double>& x) const {
    return x == last_x_ ? &last_jacobian_ : nullptr;
  }

 private:
  Predictor& predictor_;
  std::vector<FitParameter>& parameters_;
  std::vector<std::size_t> free_;
  mutable std::vector<double> last_x_, last_jacobian_;
};

// 1-sigma of the free parameters from (J^T J)^-1 at the solution (residuals in noise units).
void set_sigmas(const SimulationCost& cost, std::vector<FitParameter>& p, const std::vector<std::size_t>& free,
                const std::vector<double>& x) {
  const auto n = static_cast<std::size_t>(cost.num_residuals());
  const std::size_t m = free.size();
  std::vector<double> jac;
  if (const std::vector<double>* last = cost.jacobian_at(x)) {
    jac = *last;
  } else {
    std::vector<double> r(n);
    jac.resize(n * m);
    const double* xs[] = {x.data()};
    double* js[] = {jac.data()};
    cost.Evaluate(xs, r.data(), js);
  }
  const Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>> J(
      jac.data(), static_cast<Eigen::Index>(n), static_cast<Eigen::Index>(m));
  const Eigen::MatrixXd info = J.transpose() * J;
  const Eigen::MatrixXd cov = info.completeOrthogonalDecomposition().pseudoInverse();
  for (std::size_t j = 0; j < m; ++j) {
    const double v = cov(static_cast<Eigen::Index>(j), static_cast<Eigen::Index>(j));
    p[free[j]].sigma = v > 0 ? std::sqrt(v) : NAN;
  }
}

}  // namespace

simulation::RockerBogieEffects effects_of(const simulation::RockerBogieEffects& scenario,
                                          const std::vector<FitParameter>& parameters) {
  simulation::RockerBogieEffects fx = scenario;
  for (const auto& p : parameters) simulation::set_effect(fx, p.spec.effect, p.value);
  return fx;
}

double chi2(Predictor& predictor, const simulation::RockerBogieEffects& effects, Part part) {
  double s = 0;
  for (double r : predictor.residuals(effects, part)) s += r * r;
  return s;
}

namespace {

// The indices and values of the parameters a fit moves; a held parameter
// that is never fitted gets its stated resolution as its sigma.
void free_parameters(std::vector<FitParameter>& parameters, std::vector<std::size_t>& free, std::vector<double>& x) {
  for (std::size_t j = 0; j < parameters.size(); ++j) {
    if (!parameters[j].spec.fitted) {
      parameters[j].sigma = parameters[j].spec.resolution;
    } else if (parameters[j].free) {
      free.push_back(j);
      x.push_back(parameters[j].value);
    }
  }
}

}  // namespace

double linearised_chi2(Predictor& predictor, std::vector<FitParameter>& parameters) {
  std::vector<std::size_t> free;
  std::vector<double> x;
  free_parameters(parameters, free, x);
  const SimulationCost cost(predictor, parameters, free);
  const auto n = static_cast<std::size_t>(cost.num_residuals());
  const std::size_t m = free.size();
  std::vector<double> r(n), jac(n * m);
  const double* xs[] = {x.data()};
  double* js[] = {jac.data()};
  cost.Evaluate(xs, r.data(), m > 0 ? js : nullptr);
  const Eigen::Map<const Eigen::VectorXd> rv(r.data(), static_cast<Eigen::Index>(n));
  if (m == 0) return rv.squaredNorm();
  const Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>> J(
      jac.data(), static_cast<Eigen::Index>(n), static_cast<Eigen::Index>(m));
  const Eigen::VectorXd step = J.completeOrthogonalDecomposition().solve(-rv);
  for (std::size_t j = 0; j < m; ++j) {
    FitParameter& p = parameters[free[j]];
    p.value = std::clamp(x[j] + step(static_cast<Eigen::Index>(j)), p.spec.lower, p.spec.upper);
  }
  return (rv + J * step).squaredNorm();
}

FitOutcome fit_parameters(Predictor& predictor, std::vector<FitParameter> parameters) {
  std::vector<std::size_t> free;
  std::vector<double> x;
  free_parameters(parameters, free, x);
  if (!free.empty()) {
    ceres::Problem::Options po;
    po.cost_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
    ceres::Problem problem(po);
    SimulationCost cost(predictor, parameters, free);
    problem.AddResidualBlock(&cost, nullptr, x.data());
    for (std::size_t j = 0; j < free.size(); ++j) {
      problem.SetParameterLowerBound(x.data(), static_cast<int>(j), parameters[free[j]].spec.lower);
      problem.SetParameterUpperBound(x.data(), static_cast<int>(j), parameters[free[j]].spec.upper);
    }
    ceres::Solver::Options so;
    so.linear_solver_type = ceres::DENSE_QR;
    so.max_num_iterations = 8;
    so.function_tolerance = 1e-5;  // 1e-5 of a chi-square near the residual count: well under one unit
    so.num_threads = 1;
    so.logging_type = ceres::SILENT;
    ceres::Solver::Summary summary;
    ceres::Solve(so, &problem, &summary);
    for (std::size_t j = 0; j < free.size(); ++j) parameters[free[j]].value = x[j];
    set_sigmas(cost, parameters, free, x);
  }
  FitOutcome out;
  const simulation::RockerBogieEffects fx = effects_of(predictor.scenario_effects(), parameters);
  out.chi2_fit = chi2(predictor, fx, Part::fit);
  out.chi2_test = chi2(predictor, fx, Part::test);
  out.parameters = std::move(parameters);
  return out;
}

}  // namespace roverlab::analysis::rover
