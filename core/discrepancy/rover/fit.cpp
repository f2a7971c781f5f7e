#include "core/discrepancy/rover/fit.h"

#include <ceres/ceres.h>

#include <algorithm>
#include <cmath>
#include <numeric>

#include <Eigen/Core>

#include "core/common/error.h"
#include "core/common/thread_pool.h"
#include "core/discrepancy/dense_algebra.h"
#include "core/discrepancy/least_squares.h"
#include "core/discrepancy/study.h"

namespace roverlab::analysis::rover {

namespace {

// work(fork, 0) .. work(fork, n - 1) in parallel on the pool, each on its
// own fork of `pr`; the forks are absorbed in index order, so that the cache
// is the same on any number of threads.
template <class Work>
void on_forks(Predictor& pr, std::size_t n, const Work& work) {
  std::vector<Predictor> forks;
  forks.reserve(n);
  for (std::size_t k = 0; k < n; ++k) forks.push_back(pr.fork());
  shared_thread_pool().for_each_index(n, [&](std::size_t k) { work(forks[k], k); });
  for (const Predictor& fork : forks) pr.absorb(fork);
}

// The whitened Jacobian (n_eff x m, row-major) of raw columns at a profile.
RowMajorMatrix whitened(const GroupedLikelihood& l, const LikelihoodProfile& at, const std::vector<double>& raw,
                        std::size_t m) {
  const std::size_t n = l.effective_count();
  RowMajorMatrix J(static_cast<Eigen::Index>(n), static_cast<Eigen::Index>(m));
  std::vector<double> column(n);
  for (std::size_t j = 0; j < m; ++j) {
    l.whiten(at, raw.data() + j, column.data(), m);
    for (std::size_t i = 0; i < n; ++i) J(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) = column[i];
  }
  return J;
}

// The fit blocks' whitened residuals as a function of the free parameters;
// the Jacobian by forward differences (backward at an upper bound), or
// carried from the memo (carry_jacobian). The raw (unwhitened) Jacobian of
// the last evaluation is kept for the covariance.
class SimulationCost final : public ceres::CostFunction {
 public:
  SimulationCost(Predictor& predictor, std::vector<FitParameter>& parameters, std::vector<std::size_t> free,
                 const LikelihoodProfile& weights, JacobianMemo& memo)
      : predictor_(predictor),
        likelihood_(predictor.likelihood(Part::fit)),
        parameters_(parameters),
        free_(std::move(free)),
        weights_(weights),
        memo_(memo) {
    set_num_residuals(static_cast<int>(likelihood_.effective_count()));
    mutable_parameter_block_sizes()->push_back(static_cast<int>(free_.size()));
  }
  // A trial the simulator refuses (a soil too weak to carry the rover) is a
  // step Ceres cannot take, not the study's end.
  bool Evaluate(double const* const* x, double* residuals, double** jacobians) const override {
    try {
      return evaluate(x, residuals, jacobians);
    } catch (const DataError&) {
      return false;
    }
  }
  bool evaluate(double const* const* x, double* residuals, double** jacobians) const {
    std::vector<FitParameter> p = parameters_;
    for (std::size_t j = 0; j < free_.size(); ++j) p[free_[j]].value = x[0][j];
    const std::vector<double> r = predictor_.residuals(effects_of(predictor_.scenario_effects(), p), Part::fit);
    likelihood_.whiten(weights_, r.data(), residuals);
    if (jacobians == nullptr || jacobians[0] == nullptr) return true;
    const std::size_t m = free_.size();
    last_x_.assign(x[0], x[0] + m);
    if (!carry_jacobian(r)) forward_differences(p, r);
    const RowMajorMatrix J = whitened(likelihood_, weights_, memo_.raw, m);
    std::copy(J.data(), J.data() + J.size(), jacobians[0]);
    return true;
  }
  // The raw Jacobian computed last, when it was computed at x (saves a simulation per parameter).
  const std::vector<double>* raw_jacobian_at(const std::vector<double>& x) const {
    return x == last_x_ ? &memo_.raw : nullptr;
  }

 private:
  // The Jacobian at last_x_ without new simulations, where the one at the
  // anchor serves (issue 34, N8: each forward difference is a whole run).
  // A move under a tenth of every parameter's step is below the forward
  // difference's own resolution: the Jacobian is kept. One parameter moved
  // further: the secant from the anchor (Broyden's update in one dimension;
  // the fit converges superlinearly and the secant tends to the derivative
  // as the steps shrink). Several parameters: forward differences again.
  bool carry_jacobian(const std::vector<double>& r) const {
    const std::size_t m = free_.size();
    if (memo_.x.size() != m || memo_.r.size() != r.size() || memo_.raw.size() != r.size() * m) return false;
    double moved = 0;  // the largest move in units of the parameter's step
    for (std::size_t j = 0; j < m; ++j)
      moved = std::max(moved, std::abs(last_x_[j] - memo_.x[j]) / parameters_[free_[j]].spec.step);
    if (moved <= 0.1) return true;
    if (m != 1) return false;
    const double dx = last_x_[0] - memo_.x[0];
    for (std::size_t i = 0; i < r.size(); ++i) memo_.raw[i] = (r[i] - memo_.r[i]) / dx;
    memo_.x = last_x_;
    memo_.r = r;
    return true;
  }
  // Forward differences (backward at an upper bound): one simulation per
  // parameter, in parallel on the pool, each on a fork of the predictor
  // (absorbed in parameter order: the same cache on any number of threads).
  void forward_differences(const std::vector<FitParameter>& p, const std::vector<double>& r) const {
    const std::size_t n = r.size(), m = free_.size();
    memo_.raw.assign(n * m, 0.0);
    on_forks(predictor_, m, [&](Predictor& fork, std::size_t j) {
      std::vector<FitParameter> moved = p;
      FitParameter& q = moved[free_[j]];
      const double h = q.value + q.spec.step <= q.spec.upper ? q.spec.step : -q.spec.step;
      q.value += h;
      const std::vector<double> r2 = fork.residuals(effects_of(predictor_.scenario_effects(), moved), Part::fit);
      for (std::size_t i = 0; i < n; ++i) memo_.raw[i * m + j] = (r2[i] - r[i]) / h;
    });
    memo_.x = last_x_;
    memo_.r = r;
  }

  Predictor& predictor_;
  const GroupedLikelihood& likelihood_;
  std::vector<FitParameter>& parameters_;
  std::vector<std::size_t> free_;
  const LikelihoodProfile& weights_;
  JacobianMemo& memo_;
  mutable std::vector<double> last_x_;  // where the Jacobian was last asked for (memo_.raw serves there)
};

// 1-sigma of the free parameters from (J^T J)^-1 at the solution, J whitened
// at the solution's profile. A parameter the data do not determine (its
// column of J near zero, or lost in the others) gets NaN, never 0.
void set_sigmas(Predictor& pr, const SimulationCost& cost, std::vector<FitParameter>& p,
                const std::vector<std::size_t>& free, const std::vector<double>& x, const LikelihoodProfile& at) {
  const std::size_t m = free.size();
  std::vector<double> raw;
  if (const std::vector<double>* last = cost.raw_jacobian_at(x)) {
    raw = *last;
  } else {
    std::vector<double> r(static_cast<std::size_t>(cost.num_residuals())), jac(r.size() * m);
    const double* xs[] = {x.data()};
    double* js[] = {jac.data()};
    cost.Evaluate(xs, r.data(), js);
    raw = *cost.raw_jacobian_at(x);
  }
  const RowMajorMatrix J = whitened(pr.likelihood(Part::fit), at, raw, m);
  const Eigen::MatrixXd info = J.transpose() * J;
  const PseudoInverse pinv = pseudo_inverse(info, 1e-10);
  const bool full_rank = pinv.rank == static_cast<Eigen::Index>(m);
  const Eigen::MatrixXd& cov = pinv.matrix;
  for (std::size_t j = 0; j < m; ++j) {
    const auto jj = static_cast<Eigen::Index>(j);
    const double v = cov(jj, jj);
    const double span = p[free[j]].spec.upper - p[free[j]].spec.lower;
    // Undetermined: rank deficient, or a sigma wider than the parameter's whole range.
    p[free[j]].sigma = full_rank && v > 0 && std::sqrt(v) < span ? std::sqrt(v) : NAN;
  }
}

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

// -2 ln L on the fit blocks with the free parameters moved by dx.
double profile_at(Predictor& pr, std::vector<FitParameter> p, const std::vector<std::size_t>& free,
                  const std::vector<double>& dx) {
  for (std::size_t j = 0; j < free.size(); ++j) p[free[j]].value += dx[j];
  const std::vector<double> r = pr.residuals(effects_of(pr.scenario_effects(), p), Part::fit);
  return pr.likelihood(Part::fit).minus_two_log_l(r);
}

// The held-out yardstick: residuals in noise sigmas, encoders as increments
// (whose noise is sqrt(2) sigmas), no autocorrelation removed.
LikelihoodProfile yardstick(const GroupedLikelihood& l) {
  LikelihoodProfile y;
  for (const auto& g : l.groups()) y.groups.push_back({0.0, g.integrated ? std::sqrt(2.0) : 1.0, 0});
  return y;
}

}  // namespace

simulation::RockerBogieEffects effects_of(const simulation::RockerBogieEffects& scenario,
                                          const std::vector<FitParameter>& parameters) {
  simulation::RockerBogieEffects fx = scenario;
  for (const auto& p : parameters) simulation::set_effect(fx, p.spec.effect, p.value);
  return fx;
}

Score score(Predictor& pr, const simulation::RockerBogieEffects& effects) {
  Score s;
  const std::vector<double> fit = pr.residuals(effects, Part::fit), test = pr.residuals(effects, Part::test);
  s.profile = pr.likelihood(Part::fit).profile(fit);
  s.weights = pr.likelihood(Part::fit).fit_weights(fit);
  s.fit = s.profile.minus_two_log_l;
  const GroupedLikelihood& lt = pr.likelihood(Part::test);
  s.test = lt.minus_two_log_l(test);
  std::vector<double> w(lt.effective_count());
  lt.whiten(yardstick(lt), test.data(), w.data());
  s.held_out = rmse(w);
  return s;
}

void grid_start(Predictor& pr, std::vector<FitParameter>& parameters) {
  for (auto& p : parameters) {
    if (!(p.spec.grid > 0) || !p.free || !p.spec.fitted) continue;
    if (p.spec.grid_screen) {
      // A smooth response (a slip angle's, ~beta^2) has one basin: walk up
      // the grid from the lower bound and stop where the likelihood turns
      // (2 simulations where the effect is absent instead of the whole grid).
      double best = p.spec.lower;
      p.value = best;
      double best_f = profile_at(pr, parameters, {}, {});
      for (double v = p.spec.lower + p.spec.grid; v <= p.spec.upper + 1e-12; v += p.spec.grid) {
        p.value = v;
        const double f = profile_at(pr, parameters, {}, {});
        if (!(f < best_f)) break;
        best_f = f;
        best = v;
      }
      p.value = best;
      continue;
    }
    // The start and every grid value, each on its own fork of the predictor
    // in parallel (absorbed in order: the same cache on any number of
    // threads); the first lowest is taken, as in a walk up the grid.
    std::vector<double> values{p.value};
    for (double v = p.spec.lower; v <= p.spec.upper + 1e-12; v += p.spec.grid) values.push_back(v);
    std::vector<double> f(values.size());
    const auto at = static_cast<std::size_t>(&p - parameters.data());
    on_forks(pr, values.size(), [&](Predictor& fork, std::size_t k) {
      std::vector<FitParameter> q = parameters;
      q[at].value = values[k];
      f[k] = profile_at(fork, q, {}, {});
    });
    std::size_t best = 0;
    for (std::size_t k = 1; k < values.size(); ++k) best = f[k] < f[best] ? k : best;
    p.value = values[best];
  }
}

double linearised_fit(Predictor& predictor, std::vector<FitParameter>& parameters, const LikelihoodProfile& weights,
                      JacobianMemo& memo) {
  std::vector<std::size_t> free;
  std::vector<double> x;
  free_parameters(parameters, free, x);
  const GroupedLikelihood& l = predictor.likelihood(Part::fit);
  const SimulationCost cost(predictor, parameters, free, weights, memo);
  const std::size_t n = l.effective_count(), m = free.size();
  std::vector<double> rw(n), jac(n * m);
  const double* xs[] = {x.data()};
  double* js[] = {jac.data()};
  cost.Evaluate(xs, rw.data(), m > 0 ? js : nullptr);
  const std::vector<double> raw = predictor.residuals(effects_of(predictor.scenario_effects(), parameters), Part::fit);
  if (m == 0) return l.minus_two_log_l(raw);
  const Eigen::Map<const Eigen::VectorXd> r(rw.data(), static_cast<Eigen::Index>(n));
  const Eigen::Map<const RowMajorMatrix> J(jac.data(), static_cast<Eigen::Index>(n), static_cast<Eigen::Index>(m));
  const Eigen::VectorXd step = least_squares(J, -r);
  Eigen::VectorXd clamped(static_cast<Eigen::Index>(m));
  for (std::size_t j = 0; j < m; ++j) {
    FitParameter& p = parameters[free[j]];
    const auto jj = static_cast<Eigen::Index>(j);
    p.value = std::clamp(x[j] + step(jj), p.spec.lower, p.spec.upper);
    clamped(jj) = p.value - x[j];
  }
  // The raw residuals the linear model predicts at the clamped step, scored by the full profile.
  const std::vector<double>& rawj = *cost.raw_jacobian_at(x);
  std::vector<double> predicted = raw;
  for (std::size_t i = 0; i < predicted.size(); ++i) {
    for (std::size_t j = 0; j < m; ++j) predicted[i] += rawj[i * m + j] * clamped(static_cast<Eigen::Index>(j));
  }
  return l.minus_two_log_l(predicted);
}

namespace {

// One Ceres solve of the free parameters at fixed weights, from x (updated);
// the parameters' GN sigmas set at the solution's profile. Returns its score.
Score solve(Predictor& predictor, std::vector<FitParameter>& parameters, const std::vector<std::size_t>& free,
            std::vector<double>& x, const LikelihoodProfile& weights, int iterations, JacobianMemo& memo) {
  ceres::Problem::Options po;
  po.cost_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  ceres::Problem problem(po);
  SimulationCost cost(predictor, parameters, free, weights, memo);
  problem.AddResidualBlock(&cost, nullptr, x.data());
  for (std::size_t j = 0; j < free.size(); ++j) {
    problem.SetParameterLowerBound(x.data(), static_cast<int>(j), parameters[free[j]].spec.lower);
    problem.SetParameterUpperBound(x.data(), static_cast<int>(j), parameters[free[j]].spec.upper);
  }
  ceres::Solver::Options so;
  so.linear_solver_type = ceres::DENSE_QR;
  so.max_num_iterations = iterations;
  so.function_tolerance = 1e-5;  // 1e-5 of a cost near the residual count: well under one unit
  so.num_threads = 1;
  so.logging_type = ceres::SILENT;
  ceres::Solver::Summary summary;
  ceres::Solve(so, &problem, &summary);
  for (std::size_t j = 0; j < free.size(); ++j) parameters[free[j]].value = x[j];
  Score sc = score(predictor, effects_of(predictor.scenario_effects(), parameters));
  set_sigmas(predictor, cost, parameters, free, x, sc.profile);
  return sc;
}

// The block-robust ("sandwich") covariance of the fit: A^-1 B A^-1, A the
// Gauss-Newton information of the residuals whitened at the solution's
// profile (the weights the fit's last pass used), B the sum over time blocks
// of each block's score times its transpose, scaled by G/(G-1) for G blocks
// (White 1980; Liang & Zeger 1986, clustered). It holds where the profile's
// AR(1) noise model does not: an encoder's increments of white noise are
// MA(1) with a unit root (with the 1 urad floor of before, the profile's
// curvature also saw none of the encoders' information, and the suite's slip
// angles sat at an RMS of 0.49 sigma). Empty (the
// profile's 2 H^-1 is kept) where fewer than 20 blocks carry the
// information: a localised effect's few blocks, or a short log's, estimate B
// too loosely (with 10, a gyro bias's sigma came out 0.6 times its scatter).
Eigen::MatrixXd block_robust_covariance(Predictor& pr, const std::vector<FitParameter>& p,
                                        const std::vector<std::size_t>& free, const std::vector<double>& h,
                                        const std::vector<char>& two_sided) {
  const std::size_t m = free.size();
  const GroupedLikelihood& l = pr.likelihood(Part::fit);
  auto raw_at = [&](std::size_t j, double s) {
    std::vector<FitParameter> q = p;
    if (j < m) q[free[j]].value += s * h[j];
    return pr.residuals(effects_of(pr.scenario_effects(), q), Part::fit);
  };
  const std::vector<double> r0 = raw_at(m, 0);
  const LikelihoodProfile at = l.profile(r0);
  const std::size_t n = l.effective_count();
  std::vector<double> e0(n);
  l.whiten(at, r0.data(), e0.data());
  const std::vector<std::size_t> block = l.segments();
  const std::size_t g = block.empty() ? 0 : *std::max_element(block.begin(), block.end()) + 1;
  if (g < 20) return {};
  const auto gi = static_cast<Eigen::Index>(g), mi = static_cast<Eigen::Index>(m);
  std::vector<double> raw(r0.size() * m);  // d(residual)/d(parameter), row-major
  for (std::size_t j = 0; j < m; ++j) {
    // Central where the curvature was, else forward.
    const std::vector<double> a = raw_at(j, 1), b = two_sided[j] != 0 ? raw_at(j, -1) : r0;
    const double span = two_sided[j] != 0 ? 2 * h[j] : h[j];
    for (std::size_t i = 0; i < r0.size(); ++i) raw[i * m + j] = (a[i] - b[i]) / span;
  }
  const RowMajorMatrix J = whitened(l, at, raw, m);
  Eigen::MatrixXd score = Eigen::MatrixXd::Zero(gi, mi), info = Eigen::MatrixXd::Zero(gi, mi);
  for (std::size_t k = 0; k < n; ++k) {
    const auto bk = static_cast<Eigen::Index>(block[k]);
    const auto row = J.row(static_cast<Eigen::Index>(k));
    score.row(bk) += e0[k] * row;
    info.row(bk) += row.cwiseAbs2();
  }
  // Blocks that carry each parameter's information: (sum I_b)^2 / sum I_b^2.
  for (Eigen::Index j = 0; j < mi; ++j) {
    const double total = info.col(j).sum(), squares = info.col(j).squaredNorm();
    if (!(squares > 0) || total * total / squares < 20) return {};
  }
  const Eigen::MatrixXd A = J.transpose() * J;
  const std::optional<Eigen::MatrixXd> inverse = positive_definite_inverse(A);
  if (!inverse) return {};
  const Eigen::MatrixXd& Ai = *inverse;
  const double small_sample = static_cast<double>(g) / static_cast<double>(g - 1);
  return Ai * (small_sample * score.transpose() * score) * Ai;
}

// The profile curvature's cross terms H_jk (j < k), every evaluation in
// parallel (on_forks): central where both parameters can step both ways (four
// evaluations), else forward (h points into the bounds). at(predictor, j,
// sj, k, sk): -2 ln L with parameter j moved by sj h_j and k by sk h_k.
template <class At>
void cross_curvatures(Predictor& pr, const At& at, const std::vector<char>& two_sided, const std::vector<double>& plus,
                      const std::vector<double>& h, double f0, Eigen::MatrixXd& H) {
  struct Cross {
    std::size_t j, k;
    double sj, sk;
  };
  const std::size_t m = plus.size();
  std::vector<Cross> cross;
  for (std::size_t j = 0; j < m; ++j) {
    for (std::size_t k = j + 1; k < m; ++k) {
      if (two_sided[j] && two_sided[k]) {
        for (const auto& [sj, sk] : {std::pair{1.0, 1.0}, {1.0, -1.0}, {-1.0, 1.0}, {-1.0, -1.0}})
          cross.push_back({j, k, sj, sk});
      } else {
        cross.push_back({j, k, 1.0, 1.0});
      }
    }
  }
  std::vector<double> f(cross.size());
  on_forks(pr, cross.size(),
           [&](Predictor& fork, std::size_t t) { f[t] = at(fork, cross[t].j, cross[t].sj, cross[t].k, cross[t].sk); });
  std::size_t t = 0;
  for (std::size_t j = 0; j < m; ++j) {
    for (std::size_t k = j + 1; k < m; ++k) {
      double v = 0;
      if (two_sided[j] && two_sided[k]) {
        v = (f[t] - f[t + 1] - f[t + 2] + f[t + 3]) / (4 * h[j] * h[k]);
        t += 4;
      } else {
        v = (f[t] - plus[j] - plus[k] + f0) / (h[j] * h[k]);
        t += 1;
      }
      H(static_cast<Eigen::Index>(j), static_cast<Eigen::Index>(k)) = v;
      H(static_cast<Eigen::Index>(k), static_cast<Eigen::Index>(j)) = v;
    }
  }
}

// +-1 sigma from the curvature of the profile likelihood itself (central
// second differences of -2 ln L, noise scales and autocorrelations
// re-profiled at every point): cov = 2 H^-1. Steps of three Gauss-Newton
// sigmas, within a hundredth of the parameter's own step and that step (a
// quarter of it made the soil's first two trials rises of 600, shrunk and
// simulated again; issue 34, N8; the step itself where no sigma), shrunk where
// they leave the quadratic region, one-sided at a bound. A direction in which -2 ln L does not curve up is not
// determined: NaN. Costs 2m + 2m(m-1) evaluations. Where the information is
// spread over enough blocks, the block-robust covariance replaces 2 H^-1.
void profile_sigmas(Predictor& pr, std::vector<FitParameter>& p, const std::vector<std::size_t>& free, double f0) {
  const std::size_t m = free.size();
  std::vector<double> h(m);
  for (std::size_t j = 0; j < m; ++j) {
    const FitParameter& q = p[free[j]];
    h[j] =
        std::isfinite(q.sigma) && q.sigma > 0 ? std::clamp(3 * q.sigma, q.spec.step / 100, q.spec.step) : q.spec.step;
    // Inside the bounds on both sides where it can be.
    if (q.value + h[j] > q.spec.upper) h[j] = -h[j];
  }
  auto at = [&](Predictor& on, std::size_t a, double sa, std::size_t b, double sb) {
    std::vector<double> dx(m, 0.0);
    dx[a] += sa * h[a];
    if (b < m) dx[b] += sb * h[b];
    return profile_at(on, p, free, dx);
  };
  // The evaluations run in parallel (on_forks): first every parameter's two
  // steps (plus and minus; plus and twice plus at a bound), then each
  // step shrunk in sequence where it must be, then every pair's cross terms.
  Eigen::MatrixXd H(static_cast<Eigen::Index>(m), static_cast<Eigen::Index>(m));
  std::vector<double> plus(m), second(m);  // second: minus; f(x + 2h) one-sided
  std::vector<char> two_sided(m, 0);
  for (std::size_t j = 0; j < m; ++j) {
    const FitParameter& q = p[free[j]];
    two_sided[j] = q.value - std::abs(h[j]) >= q.spec.lower && q.value + std::abs(h[j]) <= q.spec.upper ? 1 : 0;
  }
  const auto steps = [&](const std::vector<std::size_t>& of) {  // both steps of each, in parallel
    on_forks(pr, 2 * of.size(), [&](Predictor& fork, std::size_t t) {
      const std::size_t i = of[t / 2];
      if (t % 2 == 0) {
        plus[i] = at(fork, i, 1, m, 0);
      } else {
        second[i] = at(fork, i, two_sided[i] ? -1 : 2, m, 0);
      }
    });
  };
  std::vector<std::size_t> all(m);
  std::iota(all.begin(), all.end(), std::size_t{0});
  steps(all);
  for (std::size_t j = 0; j < m; ++j) {
    const FitParameter& q = p[free[j]];
    const auto jj = static_cast<Eigen::Index>(j);
    if (!two_sided[j]) {  // f(x), f(x+h), f(x+2h)
      H(jj, jj) = (second[j] - 2 * plus[j] + f0) / (h[j] * h[j]);
      continue;
    }
    // A step far outside the quadratic region (a rise of more than 50 where
    // one sigma is a rise of 1) is shrunk towards a rise of 9, up to 3 times.
    for (int shrink = 0; shrink < 3; ++shrink) {
      const double rise = 0.5 * (plus[j] + second[j]) - f0;
      if (!(rise > 50) || std::abs(h[j]) < q.spec.step / 1000) break;
      h[j] *= std::sqrt(9 / rise);
      steps({j});
    }
    H(jj, jj) = (plus[j] - 2 * f0 + second[j]) / (h[j] * h[j]);
  }
  cross_curvatures(pr, at, two_sided, plus, h, f0, H);
  const std::optional<EigenvalueRange> eigenvalues = symmetric_eigenvalue_range(H);
  const bool curved = eigenvalues && eigenvalues->min > 0;
  const Eigen::MatrixXd cov = curved ? Eigen::MatrixXd(2 * lu_inverse(H)) : Eigen::MatrixXd();
  Eigen::MatrixXd use = cov;
  if (curved) {
    const Eigen::MatrixXd robust = block_robust_covariance(pr, p, free, h, two_sided);
    if (robust.size() > 0) use = robust;
  }
  for (std::size_t j = 0; j < m; ++j) {
    const auto jj = static_cast<Eigen::Index>(j);
    const double span = p[free[j]].spec.upper - p[free[j]].spec.lower;
    const double v = curved ? use(jj, jj) : NAN;
    p[free[j]].sigma = v > 0 && std::sqrt(v) < span ? std::sqrt(v) : NAN;
  }
}

// The curvature's sigmas; a trial the simulator refuses (a step past an
// effect's range) leaves them not determined rather than ending the study.
void set_profile_sigmas(Predictor& pr, std::vector<FitParameter>& p, const std::vector<std::size_t>& free, double f0) {
  try {
    profile_sigmas(pr, p, free, f0);
  } catch (const DataError&) {
    for (std::size_t j : free) p[j].sigma = NAN;
  }
}

}  // namespace

// Two passes: at the start model's weights (8 iterations), then at the
// first solution's own profile (its noise scales and autocorrelations, 3
// iterations from there), which moves the solution to the profile
// likelihood's optimum; the better one is kept, with its sigmas from the
// profile likelihood's curvature when asked for.
FitOutcome fit_parameters(Predictor& predictor, std::vector<FitParameter> parameters, const LikelihoodProfile& weights,
                          bool with_sigmas, JacobianMemo* carried) {
  std::vector<std::size_t> free;
  std::vector<double> x;
  free_parameters(parameters, free, x);
  JacobianMemo own;
  JacobianMemo& memo = carried != nullptr ? *carried : own;
  FitOutcome out;
  if (free.empty()) {
    out.score = score(predictor, effects_of(predictor.scenario_effects(), parameters));
    out.parameters = std::move(parameters);
    return out;
  }
  out.score = solve(predictor, parameters, free, x, weights, 8, memo);
  std::vector<FitParameter> second = parameters;
  std::vector<double> x2 = x;
  const Score s2 = solve(predictor, second, free, x2, out.score.profile, 3, memo);
  if (s2.fit < out.score.fit) {
    out.score = s2;
    parameters = std::move(second);
  }
  if (with_sigmas) set_profile_sigmas(predictor, parameters, free, out.score.fit);
  out.parameters = std::move(parameters);
  return out;
}

void set_sigmas(Predictor& predictor, std::vector<FitParameter>& parameters, double minus_two_log_l) {
  std::vector<std::size_t> free;
  std::vector<double> x;
  for (auto& p : parameters) p.free = true;
  free_parameters(parameters, free, x);
  if (!free.empty()) set_profile_sigmas(predictor, parameters, free, minus_two_log_l);
}

}  // namespace roverlab::analysis::rover
