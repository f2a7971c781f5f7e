// The discrepancy studies' one regression and one RMSE (core/discrepancy/study.h, issue 42).
#include "core/discrepancy/study.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>

#include <cmath>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "core/common/thread_pool.h"
#include "core/discrepancy/dense_algebra.h"
#include "core/discrepancy/least_squares.h"

namespace roverlab::analysis {
namespace {

TEST(DiscrepancyStudy, RegressRecoversSlopeAndTStatistic) {
  // y = 2 + 0.5 x + noise (sd 0.1) on x = 0..199: slope within 3 se; t = slope / se with
  // se = sd / sqrt(Sxx), Sxx = n (n^2 - 1) / 12.
  std::mt19937 rng(4);
  std::normal_distribution<double> noise(0.0, 0.1);
  std::vector<double> x, y;
  for (int k = 0; k < 200; ++k) {
    x.push_back(k);
    y.push_back(2.0 + 0.5 * k + noise(rng));
  }
  const Trend t = regress(x, y);
  const double se = 0.1 / std::sqrt(200.0 * (200.0 * 200.0 - 1.0) / 12.0);
  EXPECT_NEAR(t.slope, 0.5, 3 * se);
  EXPECT_NEAR(t.t, 0.5 / se, 0.1 * 0.5 / se);
  EXPECT_TRUE(t.measured());
}

TEST(DiscrepancyStudy, RegressSkipsPairsWithANonFiniteValue) {
  const std::vector<double> x = {0, 1, NAN, 2, 3, 4}, y = {1, 3.1, 100, 4.9, INFINITY, 9.0};
  const std::vector<double> xf = {0, 1, 2, 4}, yf = {1, 3.1, 4.9, 9.0};
  const Trend with_gaps = regress(x, y), finite = regress(xf, yf);
  EXPECT_DOUBLE_EQ(with_gaps.slope, finite.slope);
  EXPECT_DOUBLE_EQ(with_gaps.t, finite.t);
  EXPECT_NEAR(finite.slope, 2.0, 0.05);
}

TEST(DiscrepancyStudy, NoTrendWithoutThreeFinitePairsOrAVaryingX) {
  EXPECT_FALSE(regress({1, 2, NAN}, {1, 2, 3}).measured());
  EXPECT_TRUE(std::isnan(regress({1, 2}, {1, 2}).t));
  // x constant up to rounding (1e-9 relative): no slope is invented from it.
  EXPECT_FALSE(regress({1e3, 1e3 + 1e-10, 1e3, 1e3 - 1e-10}, {0, 5, 1, 3}).measured());
  EXPECT_TRUE(regress({0, 1e-4, 2e-4, 3e-4}, {0, 5, 1, 3}).measured());
}

TEST(DiscrepancyStudy, ResidualsOnALineHaveAnInfiniteTAndAFlatOneNone) {
  const Trend sloped = regress({0, 1, 2, 3}, {1, 3, 5, 7});
  EXPECT_DOUBLE_EQ(sloped.slope, 2.0);
  EXPECT_TRUE(std::isinf(sloped.t) && sloped.t > 0);
  const Trend flat = regress({0, 1, 2, 3}, {0, 0, 0, 0});
  EXPECT_EQ(flat.slope, 0.0);
  EXPECT_TRUE(std::isnan(flat.t));
}

TEST(DiscrepancyStudy, RmsePerValueAndPerPair) {
  EXPECT_DOUBLE_EQ(rmse({3, -4}), std::sqrt(12.5));
  // (east, north) = (3, 4) and (0, 0): horizontal errors 5 and 0, RMS sqrt(12.5).
  EXPECT_DOUBLE_EQ(rmse({3, 4, 0, 0}, 2.0), std::sqrt(12.5));
  EXPECT_TRUE(std::isnan(rmse({})));
}

// A toy study on the forward-selection skeleton (select_forward): y is
// 3 x2 + 1 x0 + noise; three candidate regressors x0, x1 and x2 (x1 unrelated
// to y). A trial is the least-squares fit of y on the chain's columns and
// the candidate's; its BIC n ln(RSS / n) + k ln n; the rule keeps a step
// that lowers BIC by more than 10.
struct ToyStudy {
  struct Trial {
    double bic = NAN;
    std::size_t candidate = 0;
  };
  std::vector<std::vector<double>> x;
  std::vector<double> y;
  double bic = 0;                  // the chain's
  std::vector<Trial> steps;        // what joined, in order
  std::vector<std::size_t> tried;  // the candidates a round tried, in order

  double bic_of(const std::vector<std::size_t>& columns) const {
    const auto n = static_cast<Eigen::Index>(y.size());
    Eigen::MatrixXd a(n, static_cast<Eigen::Index>(columns.size()) + 1);
    Eigen::VectorXd b(n);
    for (Eigen::Index r = 0; r < n; ++r) {
      a(r, 0) = 1.0;
      for (std::size_t c = 0; c < columns.size(); ++c)
        a(r, static_cast<Eigen::Index>(c) + 1) = x[columns[c]][static_cast<std::size_t>(r)];
      b(r) = y[static_cast<std::size_t>(r)];
    }
    const Eigen::VectorXd coef = a.colPivHouseholderQr().solve(b);
    const double rss = (a * coef - b).squaredNorm();
    return static_cast<double>(n) * std::log(rss / static_cast<double>(n)) +
           static_cast<double>(a.cols()) * std::log(static_cast<double>(n));
  }
  bool open(const std::vector<std::size_t>& /*chain*/, std::size_t i) {
    tried.push_back(i);
    return true;
  }
  Trial trial(const std::vector<std::size_t>& chain, std::size_t i) const {
    std::vector<std::size_t> columns = chain;
    columns.push_back(i);
    return {bic_of(columns), i};
  }
  int best(const std::vector<std::size_t>& open, const std::vector<Trial>& trials) const {
    return best_trial(open, trials, [](const Trial& a, const Trial& b) { return a.bic < b.bic; });
  }
  bool accept(const std::vector<std::size_t>& /*chain*/, std::size_t /*i*/, const Trial& t) const {
    return t.bic - bic < -10.0;
  }
  void join(std::vector<std::size_t>& chain, std::size_t i, Trial&& t) {
    chain.push_back(i);
    bic = t.bic;
    steps.push_back(t);
  }
};

ToyStudy toy_study() {
  ToyStudy s;
  std::mt19937 rng(42);
  std::normal_distribution<double> unit(0.0, 1.0);
  s.x.assign(3, std::vector<double>(200));
  for (std::size_t k = 0; k < 200; ++k) {
    for (auto& column : s.x) column[k] = unit(rng);
    s.y.push_back(3.0 * s.x[2][k] + 1.0 * s.x[0][k] + 0.5 * unit(rng));
  }
  s.bic = s.bic_of({});
  return s;
}

TEST(StudySkeleton, ForwardSelectionTakesTheBestFirstAndStopsByTheRule) {
  ToyStudy s = toy_study();
  std::vector<std::size_t> chain;
  select_forward(s, 3, 3, chain);
  // x2 explains most of y, x0 the rest; x1 gains no 10 in BIC.
  EXPECT_EQ(chain, (std::vector<std::size_t>{2, 0}));
  ASSERT_EQ(s.steps.size(), 2u);
  // The best first: x2 alone beats x0 and x1 alone.
  EXPECT_EQ(s.steps[0].bic, s.bic_of({2}));
  EXPECT_LT(s.bic_of({2}), s.bic_of({0}));
  EXPECT_LT(s.bic_of({2}), s.bic_of({1}));
  EXPECT_LT(s.steps[1].bic, s.steps[0].bic - 10.0);
  EXPECT_GT(s.bic_of({2, 0, 1}) - s.steps[1].bic, -10.0);  // the step refused
  // Three rounds: all three candidates, then the two not in the chain, then x1.
  EXPECT_EQ(s.tried, (std::vector<std::size_t>{0, 1, 2, 0, 1, 1}));
}

TEST(StudySkeleton, ForwardSelectionStopsAtMaxSteps) {
  ToyStudy s = toy_study();
  std::vector<std::size_t> chain;
  select_forward(s, 3, 1, chain);
  EXPECT_EQ(chain, (std::vector<std::size_t>{2}));
}

TEST(StudySkeleton, ForwardSelectionIsTheSameOnOneAndThreeThreads) {
  std::vector<std::vector<double>> bics;
  for (std::size_t threads : {1u, 3u}) {
    set_thread_count(threads);
    ToyStudy s = toy_study();
    std::vector<std::size_t> chain;
    select_forward(s, 3, 3, chain);
    std::vector<double> b;
    for (const auto& step : s.steps) b.push_back(step.bic);
    EXPECT_EQ(chain, (std::vector<std::size_t>{2, 0})) << threads;
    bics.push_back(b);
  }
  set_thread_count(default_thread_count());
  EXPECT_EQ(bics[0], bics[1]);  // bit-identical
}

// A study that says how long its trials take (expected_cost): on one thread
// they start longest first, ties in candidate order, and the selection is
// the same as without the hook.
struct CostedToyStudy : ToyStudy {
  std::vector<double> cost{1.0, 5.0, 1.0};  // candidate 1's trial is the long one
  mutable std::vector<std::size_t> started;
  double expected_cost(std::size_t i) const { return cost[i]; }
  Trial trial(const std::vector<std::size_t>& chain, std::size_t i) const {
    started.push_back(i);  // one thread: no race
    return ToyStudy::trial(chain, i);
  }
};

TEST(StudySkeleton, TrialsStartLongestFirstWhenTheStudySaysHowLongTheyTake) {
  set_thread_count(1);
  CostedToyStudy s;
  static_cast<ToyStudy&>(s) = toy_study();
  std::vector<std::size_t> chain;
  select_forward(s, 3, 3, chain);
  set_thread_count(default_thread_count());
  EXPECT_EQ(chain, (std::vector<std::size_t>{2, 0}));
  // Round 1: 1 (cost 5), then 0 and 2; round 2: 1, then 0; round 3: 1.
  EXPECT_EQ(s.started, (std::vector<std::size_t>{1, 0, 2, 1, 0, 1}));
  EXPECT_EQ(s.tried, (std::vector<std::size_t>{0, 1, 2, 0, 1, 1}));  // opened in candidate order
}

struct ToyStep {
  std::string name;
  double error = 0;  // held-out, after this step
  bool at_bound = false;
  double gain_share = NAN;
  StepRole role = StepRole::cause;
};

TEST(StudySkeleton, StepsWeighedByTheirShareOfTheHeldOutGain) {
  // Held-out error 10 -> 4 -> 3.95 -> 3.5 (the last step at its bound).
  std::vector<ToyStep> steps{{"a", 4.0}, {"a + b", 3.95}, {"a + b + c", 3.5, true}};
  double before = 10.0;
  weigh_steps(
      steps, 10.0, 3.5,
      [&](const ToyStep& s) {
        const double w = without_step(3.5, before, s.error);
        before = s.error;
        return w;
      },
      [](const ToyStep& s) { return step_role(s.at_bound, s.gain_share, kNegligibleGainShare); });
  EXPECT_NEAR(steps[0].gain_share, 6.0 / 6.5, 1e-12);
  EXPECT_NEAR(steps[1].gain_share, 0.05 / 6.5, 1e-12);  // under 1 %
  EXPECT_NEAR(steps[2].gain_share, 0.45 / 6.5, 1e-12);
  EXPECT_EQ(steps[0].role, StepRole::cause);
  EXPECT_EQ(steps[1].role, StepRole::also_consistent);
  EXPECT_EQ(steps[2].role, StepRole::at_bound);
  const auto text = [](const ToyStep& s) { return step_share_text(s.name, s.gain_share); };
  const StepLists together = list_steps(steps, text, ", then ");
  EXPECT_EQ(together.causes, 1);
  EXPECT_EQ(together.named, "a (92.3 % of the held-out gain)");
  EXPECT_EQ(together.also, "b (0.769 % of the held-out gain); c (6.92 % of the held-out gain)");
  const StepLists apart = list_steps(steps, text, ", then ", true);
  EXPECT_EQ(apart.also, "b (0.769 % of the held-out gain)");
  EXPECT_EQ(apart.bound, "c (6.92 % of the held-out gain)");
}

// The decompositions the studies weigh their fits with, compiled once (dense_algebra.h, least_squares.h).
TEST(DenseAlgebra, EigenvalueRangeAndInversesOfKnownMatrices) {
  // R diag(1, 4, 9) R^T with R a rotation: eigenvalues 1 and 9 at the ends.
  const Eigen::Matrix3d R = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  const Eigen::MatrixXd A = R * Eigen::Vector3d(1, 4, 9).asDiagonal() * R.transpose();
  const std::optional<EigenvalueRange> range = symmetric_eigenvalue_range(A);
  ASSERT_TRUE(range.has_value());
  EXPECT_NEAR(range->min, 1.0, 1e-12);
  EXPECT_NEAR(range->max, 9.0, 1e-12);
  EXPECT_TRUE((A * lu_inverse(A)).isIdentity(1e-12));
  const std::optional<Eigen::MatrixXd> pd = positive_definite_inverse(A);
  ASSERT_TRUE(pd.has_value());
  EXPECT_TRUE((A * *pd).isIdentity(1e-12));
  // Indefinite (eigenvalues 1 and -1) and singular: no positive-definite inverse.
  EXPECT_FALSE(positive_definite_inverse(Eigen::Vector2d(1, -1).asDiagonal().toDenseMatrix()).has_value());
  EXPECT_FALSE(positive_definite_inverse(Eigen::MatrixXd::Zero(2, 2)).has_value());
}

TEST(DenseAlgebra, PseudoInverseFindsTheRankAndLeastSquaresTheMinimumNorm) {
  // Rank 2 in 3 dimensions: u u^T + v v^T.
  const Eigen::Vector3d u(1, 0, 1), v(0, 2, -1);
  const Eigen::MatrixXd A = u * u.transpose() + v * v.transpose();
  const PseudoInverse p = pseudo_inverse(A, 1e-10);
  EXPECT_EQ(p.rank, 2);
  EXPECT_TRUE((A * p.matrix * A).isApprox(A, 1e-12));
  EXPECT_TRUE(p.matrix.isApprox(p.matrix.transpose(), 1e-12));
  EXPECT_EQ(pseudo_inverse(Eigen::MatrixXd::Identity(4, 4), 1e-10).rank, 4);
  // Over-determined and consistent: the exact solution.
  RowMajorMatrix J(4, 2);
  J << 1, 0, 0, 1, 1, 1, 2, -1;
  const Eigen::Vector2d x(0.3, -1.2);
  EXPECT_TRUE(least_squares(J, J * x).isApprox(x, 1e-12));
  // Under-determined (x1 + x2 + x3 = 3): the minimum-norm solution (1, 1, 1).
  const RowMajorMatrix row = RowMajorMatrix::Ones(1, 3);
  EXPECT_TRUE(least_squares(row, Eigen::VectorXd::Constant(1, 3.0)).isApprox(Eigen::Vector3d(1, 1, 1), 1e-12));
}

}  // namespace
}  // namespace roverlab::analysis
