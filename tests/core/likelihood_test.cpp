// The discrepancy studies' likelihood (issue 29): per-group noise scale and
// lag-1 autocorrelation profiled out, increments for integrated groups.
#include "core/discrepancy/likelihood.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace roverlab::analysis {
namespace {

std::vector<double> ar1(std::size_t n, double rho, double sd, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> g(0, sd);
  std::vector<double> x(n);
  double prev = 0;
  for (double& v : x) v = prev = rho * prev + g(rng);
  return x;
}

TEST(Likelihood, ProfilesEachGroupsScaleAndAutocorrelation) {
  std::vector<double> a = ar1(20000, 0.8, 2.0, 1), b = ar1(20000, 0.0, 0.01, 2);
  std::vector<double> r = a;
  r.insert(r.end(), b.begin(), b.end());
  const GroupedLikelihood l({{"a", a.size(), false, 1e-9, true}, {"b", b.size(), false, 1e-9, true}});
  const LikelihoodProfile p = l.profile(r);
  EXPECT_NEAR(p.groups[0].rho, 0.8, 0.01);
  EXPECT_NEAR(p.groups[0].scale, 2.0, 0.03);
  EXPECT_NEAR(p.groups[1].rho, 0.0, 0.02);
  EXPECT_NEAR(p.groups[1].scale, 0.01, 2e-4);
  // -2 ln L = sum n_g ln s_g^2 over the residuals with a lag.
  const double expected =
      20000 * std::log(p.groups[0].scale * p.groups[0].scale) + 20000 * std::log(p.groups[1].scale * p.groups[1].scale);
  EXPECT_NEAR(p.minus_two_log_l, expected, 1e-6 * std::abs(expected));
  EXPECT_EQ(l.effective_count(), 2 * 20000U);
}

TEST(Likelihood, AnIntegratedGroupIsComparedByItsIncrements) {
  // A random walk: its increments are white with sd 0.5.
  std::vector<double> w = ar1(10000, 1.0, 0.5, 3);
  const GroupedLikelihood integrated({{"w", w.size(), true, 1e-9, true}});
  const LikelihoodProfile p = integrated.profile(w);
  EXPECT_NEAR(p.groups[0].rho, 0.0, 0.03);
  EXPECT_NEAR(p.groups[0].scale, 0.5, 0.01);
  EXPECT_EQ(integrated.effective_count(), 9999U);
}

TEST(Likelihood, OneBadlyExplainedGroupDoesNotSetAnothersScale) {
  // Halving group b's misfit changes -2 ln L by n_b ln(1/4), whatever group a's misfit is.
  std::vector<double> a = ar1(1000, 0, 1000.0, 4), b = ar1(1000, 0, 1.0, 5);
  const GroupedLikelihood l({{"a", 1000, false, 1e-9, false}, {"b", 1000, false, 1e-9, false}});
  std::vector<double> r = a, r2 = a;
  r.insert(r.end(), b.begin(), b.end());
  for (double v : b) r2.push_back(v / 2);
  EXPECT_NEAR(l.minus_two_log_l(r2) - l.minus_two_log_l(r), 1000 * std::log(0.25), 1e-6);
}

TEST(Likelihood, SegmentsStartWithoutAPredecessorAndTheFloorHolds) {
  const std::vector<double> r(10, 0.0);
  const GroupedLikelihood l({{"z", 10, false, 0.1, true}}, {1, 0, 0, 0, 0, 1, 0, 0, 0, 0});
  EXPECT_EQ(l.effective_count(), 10U);
  const LikelihoodProfile p = l.profile(r);
  EXPECT_DOUBLE_EQ(p.groups[0].scale, 0.1);  // exact zeros: the floor, not ln 0
  EXPECT_TRUE(std::isfinite(p.minus_two_log_l));
}

// The block-robust covariance sums scores by block of time: each whitened
// residual's segment ordinal, the same in every group; an integrated group's
// first residual of a segment has no increment and no entry.
TEST(Likelihood, EachWhitenedResidualKnowsItsBlockOfTime) {
  const GroupedLikelihood l({{"level", 6, false, 0.1, true}, {"angle", 6, true, 0.1, true}},
                            {1, 0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0});
  const std::vector<std::size_t> expected{0, 0, 0, 1, 1, 1, 0, 0, 1, 1};
  EXPECT_EQ(l.segments(), expected);
  EXPECT_EQ(l.segments().size(), l.effective_count());
}

TEST(Likelihood, ALevelOffsetInABlockIsNotFreeWhateverTheAutocorrelation) {
  // Noise 0.01 in ten blocks of 50; one block offset by 1. The offset block's
  // first innovation carries the offset, so -2 ln L rises by far more than
  // a noise-only change would, although rho goes to about 1.
  std::vector<double> r = ar1(500, 0, 0.01, 7), shifted = r;
  std::vector<char> start(500, 0);
  for (std::size_t b = 0; b < 10; ++b) start[b * 50] = 1;
  for (std::size_t k = 200; k < 250; ++k) shifted[k] += 1.0;
  const GroupedLikelihood l({{"r", 500, false, 1e-9, true}}, start);
  EXPECT_GT(l.minus_two_log_l(shifted) - l.minus_two_log_l(r), 1000.0);
}

TEST(Likelihood, WhitenedResidualsAtTheirOwnProfileHaveUnitMeanSquare) {
  std::vector<double> r = ar1(5000, 0.6, 3.0, 6);
  const GroupedLikelihood l({{"r", r.size(), false, 1e-9, true}});
  const LikelihoodProfile p = l.profile(r);
  std::vector<double> w(l.effective_count());
  l.whiten(p, r.data(), w.data());
  double sq = 0;
  for (double v : w) sq += v * v;
  EXPECT_NEAR(sq / static_cast<double>(w.size()), 1.0, 1e-9);
}

TEST(Likelihood, NumbersAPersonReads) {
  EXPECT_EQ(format_delta_bic(-12.345), "-12.3");
  EXPECT_EQ(format_delta_bic(-123456.0), "-123,456");
  EXPECT_EQ(format_delta_bic(-2.5e11), "< -1e6");
  EXPECT_EQ(format_estimate(0.83, 0.012, "1"), "0.83 +- 0.012");
  EXPECT_EQ(format_estimate(0.83, 0.0, "m"), "0.83 m (not determined by the data)");
  EXPECT_EQ(format_estimate(0.83, NAN, "1"), "0.83 (not determined by the data)");
}

}  // namespace
}  // namespace roverlab::analysis
