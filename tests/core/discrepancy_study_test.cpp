// The discrepancy studies' one regression and one RMSE (core/discrepancy/study.h, issue 42).
#include "core/discrepancy/study.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

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

}  // namespace
}  // namespace roverlab::analysis
