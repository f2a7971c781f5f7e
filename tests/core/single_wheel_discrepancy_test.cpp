// Hidden-effect tests: single-wheel data generated with an effect picked at
// random from a seed; the study must name it and recover its parameter.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <initializer_list>
#include <random>
#include <stdexcept>
#include <vector>

#include "core/common/error.h"
#include "core/common/thread_pool.h"
#include "core/discrepancy/single_wheel/candidates.h"
#include "core/discrepancy/single_wheel/study.h"
#include "core/terramechanics/slip_angle_model.h"
#include "importers/wheel_test_csv.h"
#include "terramechanics_soils.h"
#include "tests/support/calibration_seeds.h"
#include "tests/support/resampled_wheel_test.h"
#include "tests/support/step_shares.h"

using namespace roverlab;
using namespace roverlab::terramechanics;

namespace {

struct Hidden {
  std::string effect;  // "", slip-sinkage, grousers, soil-strength, bulldozing
  Parameter parameter = Parameter::soil_strength;
  double value = 0.0;
  ModelOptions model;
};

Hidden pick_effect(unsigned seed, bool none) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  Hidden h;
  if (none) return h;
  switch (seed % 4) {
    case 0:
      h.effect = "slip-sinkage";
      h.parameter = Parameter::slip_sinkage_n1;
      h.value = 0.2 + 0.4 * u(rng);
      h.model.extensions.slip_sinkage_n1 = h.value;
      break;
    case 1:
      h.effect = "grousers";
      h.parameter = Parameter::grouser_effectiveness;
      h.value = 0.4 + 0.6 * u(rng);
      h.model.extensions.grousers = true;
      h.model.extensions.grouser_effectiveness = h.value;
      break;
    case 2:
      h.effect = "soil-strength";  // a soil 30 % weaker than described
      h.parameter = Parameter::soil_strength;
      h.value = 0.7;
      h.model.extensions.soil_strength = h.value;
      break;
    default:
      h.effect = "bulldozing";
      h.parameter = Parameter::bulldozing_scale;
      h.value = 1.0 + 2.0 * u(rng);
      h.model.extensions.bulldozing = true;
      h.model.extensions.bulldozing_scale = h.value;
      break;
  }
  return h;
}

std::vector<WheelTestPoint> testbed(const Hidden& h, unsigned seed, const MeasurementSigma& sigma) {
  std::mt19937 rng(seed * 7919u + 1u);
  std::normal_distribution<double> unit(0.0, 1.0);
  std::vector<WheelTestPoint> points;
  const Wheel wheels[] = {{0.157, 0.165, 0, 0.0}, {0.157, 0.165, 30, 0.01}};
  for (const Wheel& w : wheels) {
    for (double load : {60.0, 100.0, 140.0}) {
      for (int k = 0; k <= 7; ++k) {
        WheelTestPoint p;
        p.wheel = w;
        p.load = load;
        p.slip = 0.1 * k;
        const Traction t = evaluate(test::ding_tyii(), w, load, p.slip, h.model);
        p.drawbar_pull = t.drawbar_pull + sigma.drawbar_pull * unit(rng);
        p.torque = t.resistive_torque + sigma.torque * unit(rng);
        p.sinkage = t.sinkage + sigma.sinkage * unit(rng);
        points.push_back(p);
      }
    }
  }
  return points;
}

}  // namespace

class HiddenEffect : public ::testing::TestWithParam<unsigned> {};

TEST_P(HiddenEffect, IsNamedAndItsParameterRecovered) {
  const unsigned seed = GetParam();
  const Hidden h = pick_effect(seed, false);
  const analysis::DiscrepancyOptions options;
  const auto points = testbed(h, seed, options.sigma);
  const analysis::DiscrepancyReport r = analysis::study_single_wheel(test::ding_tyii(), points, options);
  ASSERT_TRUE(r.significant) << h.effect << ": " << r.verdict;
  ASSERT_GE(r.best, 0);
  const auto& c = r.candidates[static_cast<std::size_t>(r.best)];
  EXPECT_EQ(c.name, h.effect) << r.verdict;
  bool found = false;
  for (const auto& p : c.fit.parameters) {
    if (p.parameter != h.parameter) continue;
    found = true;
    EXPECT_LT(std::abs(p.value - h.value), 2.0 * p.sigma)
        << h.effect << ": " << to_string(p.parameter) << " = " << p.value << " +- " << p.sigma << ", truth " << h.value;
  }
  EXPECT_TRUE(found);
  // The gain is measured on held-out points, and is real: the extended model
  // predicts points it did not see to about the noise level.
  EXPECT_LT(c.held_out_score, 0.9 * r.baseline_score);
  EXPECT_LT(c.held_out_score, 1.3);
  EXPECT_LT(c.delta_bic, -10.0);
  EXPECT_NE(r.verdict.find(h.effect), std::string::npos);
}

INSTANTIATE_TEST_SUITE_P(Seeds, HiddenEffect, ::testing::Values(1u, 2u, 3u, 4u, 5u, 6u, 7u, 8u));

TEST(NegativeControl, NoEffectReportsNoSignificantDiscrepancy) {
  for (unsigned seed : {21u, 22u, 23u}) {
    const Hidden h = pick_effect(seed, true);
    const analysis::DiscrepancyOptions options;
    const auto points = testbed(h, seed, options.sigma);
    const analysis::DiscrepancyReport r = analysis::study_single_wheel(test::ding_tyii(), points, options);
    EXPECT_FALSE(r.significant) << r.verdict;
    EXPECT_NE(r.verdict.find("No significant discrepancy"), std::string::npos);
    EXPECT_LT(r.baseline_score, 1.3);  // residuals at the noise level
  }
}

// Two effects hidden at once: forward selection names both, each with its
// parameter, and the chain's held-out error is at the noise level.
TEST(TwoHiddenEffects, AreBothNamedByForwardSelection) {
  for (unsigned seed : {31u, 32u}) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    Hidden h;
    h.model.extensions.slip_sinkage_n1 = 0.3 + 0.3 * u(rng);
    h.model.extensions.grousers = true;
    h.model.extensions.grouser_effectiveness = 0.5 + 0.4 * u(rng);
    const analysis::DiscrepancyOptions options;
    const auto points = testbed(h, seed, options.sigma);
    const analysis::DiscrepancyReport r = analysis::study_single_wheel(test::ding_tyii(), points, options);
    ASSERT_EQ(r.selection.size(), 2u) << r.verdict;
    const auto& chain = r.selection.back();
    EXPECT_NE(chain.name.find("slip-sinkage"), std::string::npos) << chain.name;
    EXPECT_NE(chain.name.find("grousers"), std::string::npos) << chain.name;
    for (const auto& p : chain.fit.parameters) {
      if (p.parameter == Parameter::slip_sinkage_n1) {
        EXPECT_LT(std::abs(p.value - h.model.extensions.slip_sinkage_n1), 3.0 * p.sigma + 0.02) << p.value;
      }
      if (p.parameter == Parameter::grouser_effectiveness) {
        EXPECT_LT(std::abs(p.value - h.model.extensions.grouser_effectiveness), 3.0 * p.sigma + 0.02) << p.value;
      }
    }
    EXPECT_LT(chain.held_out_score, 1.3);
    EXPECT_LT(chain.held_out_score, r.selection.front().held_out_score);
    EXPECT_NE(r.verdict.find("Causes (forward selection)"), std::string::npos) << r.verdict;
  }
}

// Above max_leave_one_out_points the held-out scores come from folds (the cost
// stays linear in the points; leave-one-out was quadratic), and the study
// still names the effect.
TEST(HiddenEffectInFolds, IsNamedWithTenFoldHeldOutScores) {
  for (unsigned seed : {1u, 2u}) {
    const Hidden h = pick_effect(seed, false);
    analysis::DiscrepancyOptions options;
    options.max_leave_one_out_points = 20;
    const auto points = testbed(h, seed, options.sigma);
    const analysis::DiscrepancyReport r = analysis::study_single_wheel(test::ding_tyii(), points, options);
    EXPECT_EQ(r.held_out_method, "10-fold");
    ASSERT_TRUE(r.significant) << h.effect << ": " << r.verdict;
    const auto& c = r.candidates[static_cast<std::size_t>(r.best)];
    EXPECT_EQ(c.name, h.effect) << r.verdict;
    EXPECT_LT(c.held_out_score, 1.3);
  }
  analysis::DiscrepancyOptions loo;
  EXPECT_EQ(analysis::study_single_wheel(test::ding_tyii(), testbed(pick_effect(1, false), 1, loo.sigma), loo)
                .held_out_method,
            "leave-one-out");
}

// F12, F14: too few points, or all at one slip, are refused in words instead
// of a "trend" with t = 1e9 and NaN sigmas.
TEST(DegenerateTestbedData, IsRefusedNamingWhatIsMissing) {
  const analysis::DiscrepancyOptions options;
  auto points = testbed(pick_effect(1, true), 1, options.sigma);
  const std::vector<WheelTestPoint> one(points.begin(), points.begin() + 1);
  try {
    analysis::study_single_wheel(test::ding_tyii(), one, options);
    ADD_FAILURE() << "one point was studied";
  } catch (const DataError& e) {
    EXPECT_NE(std::string(e.what()).find("at least 4 points"), std::string::npos) << e.what();
  }
  for (auto& p : points) p.slip = 0.1;
  try {
    analysis::study_single_wheel(test::ding_tyii(), points, options);
    ADD_FAILURE() << "points at one slip were studied";
  } catch (const DataError& e) {
    EXPECT_NE(std::string(e.what()).find("two slips"), std::string::npos) << e.what();
  }
}

TEST(ResidualStatistics, NoTrendWhenTheSlipDoesNotVary) {
  std::vector<WheelTestPoint> points(8);
  std::vector<PointResidual> residuals;
  for (std::size_t i = 0; i < points.size(); ++i) {
    points[i].slip = 0.1;
    points[i].load = 80.0;
    residuals.push_back({i, Quantity::drawbar_pull, 0.0, 7.845, 0.5});
  }
  const auto stats = analysis::residual_statistics(residuals, points);
  ASSERT_EQ(stats.size(), 1u);
  EXPECT_EQ(stats[0].slope_vs_slip, 0.0);
  EXPECT_EQ(stats[0].t_slip, 0.0);
}

TEST(ResidualStatistics, BiasAndTrends) {
  std::vector<WheelTestPoint> points(5);
  std::vector<PointResidual> residuals;
  for (std::size_t i = 0; i < 5; ++i) {
    points[i].slip = 0.1 * static_cast<double>(i);
    points[i].load = 50.0;
    // predicted - measured = 1 + 10 s (+ a little scatter so the t statistic is finite)
    residuals.push_back({i, Quantity::drawbar_pull, 0.0, 1.0 + 10.0 * points[i].slip + (i % 2 ? 0.01 : -0.01), 0.5});
  }
  const auto stats = analysis::residual_statistics(residuals, points);
  ASSERT_EQ(stats.size(), 1u);
  EXPECT_NEAR(stats[0].bias, 3.0, 0.01);
  EXPECT_NEAR(stats[0].slope_vs_slip, 10.0, 0.1);
  EXPECT_GT(stats[0].t_slip, 50.0);
}

TEST(SingleWheelCandidates, ComeFromTheRegistryInItsOrder) {
  const auto candidates = analysis::single_wheel_candidates();
  std::vector<std::string> names;
  for (const auto& c : candidates) names.push_back(c->name());
  EXPECT_EQ(names, (std::vector<std::string>{"slip-sinkage", "grousers", "bulldozing", "soil-strength",
                                             "max-stress-angle", "slip-shear-modulus", "rear-angle", "shear-peak",
                                             "lateral-shear-modulus", "sidewall", "pile-up", "depth-scale"}));
  // RFT's own candidates belong to the RFT family only, grousers to both, the rest to Wong-Reece / Ishigami.
  for (const auto& c : candidates) {
    const std::string n = c->name();
    const bool rft_only = n == "pile-up" || n == "depth-scale";
    EXPECT_EQ(c->belongs_to(ModelKind::rft), rft_only || n == "grousers") << n;
    EXPECT_EQ(c->belongs_to(ModelKind::ishigami), !rft_only) << n;
  }
  // Only the grouser candidate needs grousers, and it switches their model on;
  // only the lateral ones need points at a slip angle.
  Extensions e;
  for (const auto& c : candidates) {
    EXPECT_EQ(c->needs_grousers(), std::string(c->name()) == "grousers") << c->name();
    EXPECT_EQ(c->needs_lateral_force(),
              std::string(c->name()) == "lateral-shear-modulus" || std::string(c->name()) == "sidewall")
        << c->name();
    c->configure(e);
  }
  EXPECT_TRUE(e.grousers);
  EXPECT_TRUE(e.bulldozing);
  EXPECT_TRUE(e.shear_peak);
}

namespace {

// The bundled Ding 2011 rows repeated to `rows` (issue 29's 5,000-row example).
std::vector<WheelTestPoint> ding_resampled(std::size_t rows) {
  return test::resampled_wheel_test(
      io::read_wheel_test_csv(std::string(ROVERLAB_TEST_DATA) + "/single_wheel/ding2011_tyii.csv"), rows);
}

bool named_in_chain(const analysis::DiscrepancyReport& r, const std::string& name) {
  return !r.selection.empty() && r.selection.back().name.find(name) != std::string::npos;
}

const analysis::QuantityVerdict& verdict_of(const analysis::DiscrepancyReport& r, Quantity q) {
  for (const auto& v : r.quantity_verdicts) {
    if (v.quantity == q) return v;
  }
  throw std::runtime_error("no verdict for a quantity");
}

}  // namespace

// Issue 29: two causes in the data, both named; the drawbar-pull misfit that
// no candidate explains no longer hides slip-sinkage's gain on sinkage.
TEST(TwoCausesInResampledDingData, GrousersAndSlipSinkageAreBothNamed) {
  const auto points = ding_resampled(1500);
  const auto r = analysis::study_single_wheel(test::ding_tyii(), points);
  EXPECT_TRUE(named_in_chain(r, "slip-sinkage")) << r.verdict;
  EXPECT_TRUE(named_in_chain(r, "grousers")) << r.verdict;
  const auto& s = verdict_of(r, Quantity::sinkage);
  EXPECT_TRUE(s.significant);
  EXPECT_EQ(s.explained_by, "slip-sinkage") << s.sentence;
  EXPECT_LT(s.held_out_after, 0.6 * s.held_out_before) << s.sentence;
}

// Issue 46: on a long file the family studied second is first studied on
// a random subset; on the Ding rows RFT loses there (as it does on
// all of them), so it is not studied on all points, and the study's result
// is the one without the screen.
TEST(FamilyScreen, OnALongFileTheLosingFamilyIsStudiedOnASubsetOnly) {
  const auto points = ding_resampled(120);
  analysis::DiscrepancyOptions o;
  o.compare_families = true;
  o.family_screen_points = 0;  // no screen
  const auto full = analysis::study_single_wheel(test::ding_tyii(), points, o);
  o.family_screen_points = 40;
  const auto screened = analysis::study_single_wheel(test::ding_tyii(), points, o);
  ASSERT_EQ(full.families.size(), 2u);
  ASSERT_EQ(screened.families.size(), 2u);
  EXPECT_EQ(full.baseline_model, "Wong-Reece") << full.family_choice;
  EXPECT_EQ(full.families[1].studied_points, 0u);
  EXPECT_EQ(screened.families[1].studied_points, 40u) << screened.family_choice;
  EXPECT_GT(screened.families[1].final_held_out_score, screened.families[0].final_held_out_score);
  EXPECT_NE(screened.family_choice.find("on 40 of the 120 points (a random subset)"), std::string::npos)
      << screened.family_choice;
  EXPECT_EQ(screened.baseline_model, full.baseline_model);
  EXPECT_EQ(screened.final_model, full.final_model);
  ASSERT_FALSE(screened.selection.empty());
  EXPECT_EQ(screened.selection.back().held_out_score, full.selection.back().held_out_score);
}

// Issue 46: on a long file each forward step ranks its trials on a random
// subset and fits only the best there on all points; the steps it takes,
// their fits and held-out scores are those of trials fitted on all points.
TEST(StepScreen, TheStepsRankedOnASubsetAreTheStepsTakenOnAllPoints) {
  const auto points = ding_resampled(240);
  analysis::DiscrepancyOptions o;
  o.step_screen_points = 0;  // every trial on all points
  const auto full = analysis::study_single_wheel(test::ding_tyii(), points, o);
  o.step_screen_points = 60;
  const auto screened = analysis::study_single_wheel(test::ding_tyii(), points, o);
  EXPECT_EQ(full.step_screen_points, 0u);
  EXPECT_EQ(screened.step_screen_points, 60u);
  ASSERT_GE(full.selection.size(), 2u) << full.verdict;  // a step after the first: the screen ranked it
  ASSERT_EQ(screened.selection.size(), full.selection.size()) << screened.final_model << " / " << full.final_model;
  for (std::size_t i = 0; i < full.selection.size(); ++i) {
    EXPECT_EQ(screened.selection[i].name, full.selection[i].name);
    EXPECT_NEAR(screened.selection[i].bic, full.selection[i].bic, 1e-6 * std::abs(full.selection[i].bic));
    EXPECT_NEAR(screened.selection[i].held_out_score, full.selection[i].held_out_score,
                1e-4 * full.selection[i].held_out_score);
  }
  EXPECT_EQ(screened.verdict, full.verdict);
}

// Issue 29: on the 34 real measurements the verdict per quantity agrees with
// the trend statistics the study prints (sinkage's slip trend t = -15).
TEST(RealDingData, TheVerdictPerQuantityAgreesWithItsTrendStatistics) {
  const auto points = io::read_wheel_test_csv(std::string(ROVERLAB_TEST_DATA) + "/single_wheel/ding2011_tyii.csv");
  const auto r = analysis::study_single_wheel(test::ding_tyii(), points);
  ASSERT_EQ(r.quantity_verdicts.size(), r.baseline.size());
  for (const auto& b : r.baseline) {
    const auto& v = verdict_of(r, b.quantity);
    const bool strong = std::abs(b.t_slip) >= 3 || std::abs(b.t_load) >= 3 || std::abs(b.t_bias) >= 3;
    EXPECT_EQ(v.significant, strong) << v.sentence;
  }
  EXPECT_TRUE(verdict_of(r, Quantity::sinkage).significant);
  EXPECT_EQ(r.verdict.find("No significant discrepancy"), std::string::npos) << r.verdict;
  EXPECT_NE(r.verdict.find("sinkage: significant"), std::string::npos) << r.verdict;
}

// Issue 29: how often the study claims a cause on data without one, at its
// threshold (target at most 5 %), on seeds the other tests do not use.
TEST(Calibration, FalseClaimsOnDataWithoutAnEffectAreRare) {
  const unsigned n = test::calibration_seeds(20);
  unsigned claims = 0, bic_alone = 0;
  for (unsigned seed = 1000; seed < 1000 + n; ++seed) {
    const auto points = testbed(pick_effect(seed, true), seed, analysis::DiscrepancyOptions{}.sigma);
    const auto r = analysis::study_single_wheel(test::ding_tyii(), points);
    claims += r.significant ? 1 : 0;
    bool any = false;
    for (const auto& c : r.candidates) any = any || (c.applicable && c.delta_bic < -10.0);
    bic_alone += any ? 1 : 0;
  }
  std::printf("no-effect runs: %u, claims: %u, BIC alone below -10: %u\n", n, claims, bic_alone);
  EXPECT_LE(claims, n / 20);
}

// Issue 29: the +-1 and +-2 sigma intervals of the named cause's parameter
// cover the hidden value about as often as they say (targets 60-75 % and
// 90-98 %; with 40 runs the test allows the binomial spread).
TEST(Calibration, TheParametersIntervalsCoverTheHiddenValue) {
  const unsigned n = test::calibration_seeds(40);
  unsigned within1 = 0, within2 = 0, count = 0;
  for (unsigned seed = 2000; seed < 2000 + n; ++seed) {
    const Hidden h = pick_effect(seed, false);
    const auto points = testbed(h, seed, analysis::DiscrepancyOptions{}.sigma);
    const auto r = analysis::study_single_wheel(test::ding_tyii(), points);
    if (r.selection.empty()) continue;
    for (const auto& p : r.selection.back().fit.parameters) {
      if (p.parameter != h.parameter || !std::isfinite(p.sigma)) continue;
      const double z = std::abs(p.value - h.value) / p.sigma;
      ++count;
      within1 += z <= 1 ? 1 : 0;
      within2 += z <= 2 ? 1 : 0;
    }
  }
  std::printf("hidden-effect runs: %u, parameters: %u, within 1 sigma: %u, within 2 sigma: %u\n", n, count, within1,
              within2);
  ASSERT_GE(count, n * 3 / 4);
  EXPECT_GE(within1, count * 50 / 100);
  EXPECT_LE(within1, count * 85 / 100);
  EXPECT_GE(within2, count * 85 / 100);
}

// Issue 33 item 4: the drawbar-pull extensions from the literature, each
// hidden alone in simulated wheel tests (four noise draws); the study names
// it first and each of its parameters' 2-sigma interval covers the truth in
// at least three draws of four (measured over 11 draws: 31 of 33 within 2
// sigma), with held-out error at the noise level. The extension is switched
// on as its candidate does (the peaked shear curve is a switch).
struct HiddenExtension {
  const char* effect;
  std::vector<std::pair<Parameter, double>> truth;
};

class HiddenDrawbarExtension : public ::testing::TestWithParam<HiddenExtension> {};

TEST_P(HiddenDrawbarExtension, IsNamedAndItsParameterRecovered) {
  const HiddenExtension e = GetParam();
  Soil soil = test::ding_tyii();
  ModelOptions model;
  for (const auto& c : analysis::single_wheel_candidates()) {
    if (c->name() == std::string(e.effect)) c->configure(model.extensions);
  }
  for (const auto& [parameter, value] : e.truth) set_parameter(soil, model.extensions, parameter, value);
  const analysis::DiscrepancyOptions options;
  std::vector<int> covered(e.truth.size(), 0);
  for (unsigned draw = 1; draw <= 4; ++draw) {
    std::mt19937 rng(draw);
    std::normal_distribution<double> unit(0.0, 1.0);
    auto points = testbed(Hidden{}, 5, options.sigma);
    for (auto& p : points) {  // the same testbed, generated with the extension on
      const Traction t = evaluate(soil, p.wheel, p.load, p.slip, model);
      p.drawbar_pull = t.drawbar_pull + options.sigma.drawbar_pull * unit(rng);
      p.torque = t.resistive_torque + options.sigma.torque * unit(rng);
      p.sinkage = t.sinkage + options.sigma.sinkage * unit(rng);
    }
    const auto r = analysis::study_single_wheel(test::ding_tyii(), points, options);
    ASSERT_FALSE(r.selection.empty()) << e.effect << ": " << r.verdict;
    const auto& c = r.selection.front();
    EXPECT_EQ(c.name, e.effect) << r.verdict;
    for (std::size_t k = 0; k < e.truth.size(); ++k) {
      bool found = false;
      for (const auto& p : c.fit.parameters) {
        if (p.parameter != e.truth[k].first) continue;
        found = true;
        covered[k] += std::abs(p.value - e.truth[k].second) < 2.0 * p.sigma ? 1 : 0;
        std::printf("%s draw %u: %s = %.4f +- %.4f (truth %.4f)\n", e.effect, draw, to_string(p.parameter), p.value,
                    p.sigma, e.truth[k].second);
      }
      EXPECT_TRUE(found) << to_string(e.truth[k].first);
    }
    EXPECT_LT(c.held_out_score, 1.3) << r.verdict;
    EXPECT_LT(c.delta_bic, -10.0);
  }
  for (std::size_t k = 0; k < e.truth.size(); ++k)
    EXPECT_GE(covered[k], 3) << e.effect << " " << to_string(e.truth[k].first);
}

// shear-peak: a dense soil whose shear stress peaks at K_w = 8 mm and falls to
// 60 % of its maximum (Wong's hump curve, model.h).
INSTANTIATE_TEST_SUITE_P(Literature, HiddenDrawbarExtension,
                         ::testing::Values(HiddenExtension{"slip-shear-modulus",
                                                           {{Parameter::shear_modulus_slip, 2.5}}},
                                           HiddenExtension{"rear-angle", {{Parameter::rear_angle_ratio, 0.3}}},
                                           HiddenExtension{"max-stress-angle", {{Parameter::c2, 0.05}}},
                                           HiddenExtension{"shear-peak",
                                                           {{Parameter::shear_residual_ratio, 0.6},
                                                            {Parameter::shear_peak_displacement, 0.008}}}));

namespace {

double held_out_drawbar(const analysis::DiscrepancyReport& r, const analysis::CandidateResult& c) {
  for (std::size_t i = 0; i < r.quantities.size(); ++i) {
    if (r.quantities[i] == Quantity::drawbar_pull) return c.held_out_rmse[i];
  }
  return NAN;
}

}  // namespace

// Issue 33 item 4: on the 12 real Ding 2011 points the drawbar-pull misfit
// (baseline RMSE 5.90 N) is cut by a third or more on held-out points by the
// chain forward selection builds from the literature's extensions, both
// leaving one point out and leaving one slip out (every point at that slip,
// both wheels); before them the chain reached 5.68 N.
TEST(RealDingData, TheLiteratureExtensionsCutTheHeldOutDrawbarPullByAThird) {
  const auto points = io::read_wheel_test_csv(std::string(ROVERLAB_TEST_DATA) + "/single_wheel/ding2011_tyii.csv");
  for (auto hold_out : {analysis::HoldOut::points, analysis::HoldOut::slip}) {
    analysis::DiscrepancyOptions options;
    options.hold_out = hold_out;
    const auto r = analysis::study_single_wheel(test::ding_tyii(), points, options);
    ASSERT_FALSE(r.selection.empty()) << r.verdict;
    const double before = r.baseline_held_out_rmse[0];
    ASSERT_EQ(r.quantities[0], Quantity::drawbar_pull);
    EXPECT_NEAR(before, 5.90, 0.01);
    const double after = held_out_drawbar(r, r.selection.back());
    EXPECT_LT(after, 0.7 * before) << r.held_out_method << ": " << r.verdict;
    EXPECT_TRUE(named_in_chain(r, "slip-shear-modulus")) << r.verdict;
    EXPECT_EQ(verdict_of(r, Quantity::drawbar_pull).explained_by, "slip-shear-modulus") << r.verdict;
    // The sentence credits the step its own cut, from the step before it (slip-sinkage
    // alone pulls no better than the baseline), not the baseline's 5.90 N.
    const auto& v = verdict_of(r, Quantity::drawbar_pull);
    std::size_t step = 0;
    while (step < r.selection.size() && r.selection[step].name != v.explained_by_chain) ++step;
    ASSERT_LT(step, r.selection.size()) << v.explained_by_chain;
    const double step_before = step == 0 ? before : held_out_drawbar(r, r.selection[step - 1]);
    EXPECT_DOUBLE_EQ(v.held_out_step_before, step_before);
    char cut[160];
    std::snprintf(cut, sizeof cut, "%.2f N -> %.2f N", step_before, v.held_out_after);
    EXPECT_NE(v.sentence.find(cut), std::string::npos) << cut << " in: " << v.sentence;
    // No candidate alone reaches 30 % (issue 33's done-when): the sentence says so with the best
    // single figure, slip-shear-modulus 5.90 N -> 4.61 N (leave-one-out) or 4.62 N (by slip).
    const analysis::CandidateResult* alone = nullptr;
    for (const auto& c : r.candidates) {
      if (c.applicable && (alone == nullptr || held_out_drawbar(r, c) < held_out_drawbar(r, *alone))) alone = &c;
    }
    ASSERT_NE(alone, nullptr);
    EXPECT_EQ(alone->name, "slip-shear-modulus");
    EXPECT_GT(held_out_drawbar(r, *alone), 0.7 * before);
    std::snprintf(cut, sizeof cut, "alone no candidate cuts it by 30 %% (best %s: %.2f N -> %.2f N, %+.0f %%)",
                  alone->name.c_str(), before, held_out_drawbar(r, *alone),
                  100.0 * (held_out_drawbar(r, *alone) / before - 1.0));
    EXPECT_NE(v.sentence.find(cut), std::string::npos) << cut << " in: " << v.sentence;
  }
}

// Holding out a whole wheel: each fold is fitted afresh, so the grousers'
// parameter, which only the grousered wheel determines, cannot be carried
// into its own prediction from the fit on all points. Hidden grousers are
// found and predicted at the noise level point by point, but not for a
// grousered wheel the fit never saw.
TEST(HoldOut, AWheelTheFitNeverSawLendsItNoParameter) {
  const Hidden h = pick_effect(1, false);
  ASSERT_EQ(h.effect, "grousers");
  const auto points = testbed(h, 1, analysis::DiscrepancyOptions{}.sigma);
  analysis::DiscrepancyOptions by_point, by_wheel;
  by_wheel.hold_out = analysis::HoldOut::wheel;
  const auto a = analysis::study_single_wheel(test::ding_tyii(), points, by_point);
  const auto b = analysis::study_single_wheel(test::ding_tyii(), points, by_wheel);
  EXPECT_EQ(b.held_out_method, "leave-one-wheel-out");
  const auto grousers = [](const analysis::DiscrepancyReport& r) {
    for (const auto& c : r.candidates) {
      if (c.name == "grousers") return c;
    }
    throw std::runtime_error("no grousers candidate");
  };
  EXPECT_LT(grousers(a).held_out_score, 1.3);
  EXPECT_GT(grousers(b).held_out_score, 1.6 * grousers(a).held_out_score);
  // One wheel only: nothing to hold out, said in words.
  std::vector<WheelTestPoint> smooth;
  for (const auto& p : points) {
    if (p.wheel.grouser_count == 0) smooth.push_back(p);
  }
  EXPECT_THROW(analysis::study_single_wheel(test::ding_tyii(), smooth, by_wheel), DataError);
  EXPECT_THROW(analysis::parse_hold_out("wheels"), DataError);
}

// Issue 33 item 3: wheel tests at slip angles, written as a CSV with the
// slip_angle_deg and lateral_force_N columns from the slip-angle model
// (Ishigami et al. 2007) with a hidden lateral shear modulus k_y (the soil's
// K_s times a factor in [1.5, 3]) and noise (0.5 N, 0.2 N m, 0.5 mm, 0.5 N).
namespace {

struct LateralTestbed {
  std::vector<WheelTestPoint> points;
  double k_y = 0.0;
};

LateralTestbed lateral_testbed(unsigned seed, double sidewall_scale = 1.0,
                               SlipDefinition definition = SlipDefinition::longitudinal,
                               std::initializer_list<double> slip_angles_deg = {0.0, 15.0, 30.0, 60.0}) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::normal_distribution<double> unit(0.0, 1.0);
  Soil soil = test::ding_tyii();
  LateralTestbed out;
  out.k_y = soil.shear_modulus * (1.5 + 1.5 * u(rng));
  soil.lateral_shear_modulus = out.k_y;
  ModelOptions model;
  model.kind = ModelKind::ishigami;
  model.extensions.sidewall_scale = sidewall_scale;
  model.slip_definition = definition;
  const std::string path = ::testing::TempDir() + "/lateral_" + std::to_string(seed) + ".csv";
  {
    std::ofstream csv(path);
    csv << "wheel,grouser_count,grouser_height_m,radius_m,width_m,load_N,slip,slip_angle_deg,drawbar_pull_N,"
           "torque_Nm,sinkage_m,lateral_force_N\n";
    const Wheel wheels[] = {{0.157, 0.165, 0, 0.0}, {0.157, 0.165, 30, 0.01}};
    for (const Wheel& w : wheels) {
      for (double load : {60.0, 120.0}) {
        for (double slip : {0.1, 0.3, 0.5}) {
          for (double beta_deg : slip_angles_deg) {
            const auto t = evaluate_slip_angle(soil, w, load, slip, beta_deg * M_PI / 180.0, model);
            csv << (w.grouser_count ? "grousered" : "smooth") << ',' << w.grouser_count << ',' << w.grouser_height
                << ',' << w.radius << ',' << w.width << ',' << load << ',' << slip << ',' << beta_deg << ','
                << t.drawbar_pull + 0.5 * unit(rng) << ',' << t.resistive_torque + 0.2 * unit(rng) << ','
                << t.sinkage + 0.0005 * unit(rng) << ',' << t.lateral_force + 0.5 * unit(rng) << '\n';
          }
        }
      }
    }
  }
  out.points = io::read_wheel_test_csv(path);
  std::remove(path.c_str());
  return out;
}

const analysis::CandidateResult* candidate_named(const analysis::DiscrepancyReport& r, const std::string& name) {
  for (const auto& c : r.candidates) {
    if (c.name == name) return &c;
  }
  return nullptr;
}

double held_out_of(const analysis::DiscrepancyReport& r, const std::vector<double>& rmse, Quantity q) {
  for (std::size_t i = 0; i < r.quantities.size(); ++i) {
    if (r.quantities[i] == q) return rmse[i];
  }
  return NAN;
}

}  // namespace

// The study reads the lateral columns, predicts with the slip-angle model,
// names the hidden lateral shear modulus, recovers it, and its held-out
// lateral-force error falls to the noise.
TEST(LateralHiddenEffect, TheLateralShearModulusIsNamedAndRecovered) {
  const auto bed = lateral_testbed(1);
  ASSERT_EQ(bed.points.size(), 48u);
  const auto r = analysis::study_single_wheel(test::ding_tyii(), bed.points);
  EXPECT_EQ(r.baseline_model, "Ishigami (slip angle)");
  EXPECT_EQ(r.slip_definition, "longitudinal") << r.slip_definition_reason;
  ASSERT_EQ(r.quantities.size(), 4u);
  EXPECT_EQ(r.quantities[3], Quantity::lateral_force);
  ASSERT_FALSE(r.selection.empty()) << r.verdict;
  EXPECT_EQ(r.selection.front().name, "lateral-shear-modulus") << r.verdict;
  const auto& p = r.selection.front().fit.parameters.at(0);
  EXPECT_EQ(p.parameter, Parameter::lateral_shear_modulus);
  EXPECT_LT(std::abs(p.value - bed.k_y), 2.0 * p.sigma) << p.value << " +- " << p.sigma << ", truth " << bed.k_y;
  const double before = held_out_of(r, r.baseline_held_out_rmse, Quantity::lateral_force);
  const double after = held_out_of(r, r.selection.front().held_out_rmse, Quantity::lateral_force);
  EXPECT_GT(before, 3.0);
  EXPECT_LT(after, 0.75);  // the 0.5 N noise, held out
  EXPECT_EQ(verdict_of(r, Quantity::lateral_force).explained_by, "lateral-shear-modulus") << r.verdict;
  // Per wheel (the figures compared with a wheel's own reference model): the
  // final model's held-out lateral-force RMSE on each wheel near the noise.
  int lateral_wheels = 0;
  for (const auto& w : r.per_wheel) {
    if (w.quantity != Quantity::lateral_force) continue;
    ++lateral_wheels;
    EXPECT_EQ(w.count, 24u) << w.wheel;
    EXPECT_LT(w.model_rmse, 0.75) << w.wheel;
    EXPECT_GT(w.baseline_rmse, 2.0) << w.wheel;
  }
  EXPECT_EQ(lateral_wheels, 2);
  // The sidewall candidate is there, and does not explain it as well.
  const auto* sidewall = candidate_named(r, "sidewall");
  ASSERT_NE(sidewall, nullptr);
  EXPECT_TRUE(sidewall->applicable);
  EXPECT_GT(held_out_of(r, sidewall->held_out_rmse, Quantity::lateral_force), 2.0 * after);
}

// A file whose slip is the travel slip 1 - |v| / (r w) (a carriage's speed),
// with and without points at 90 deg, that does not say so: the two readings
// differ, so both are reported, each complete (issue 43), the travel
// reading first: its final model predicts the held-out points to the noise;
// forced to the longitudinal reading, the same study is several times worse.
TEST(SlipDefinition, ATravelSlipFileIsReadAsTravelSlip) {
  const auto sideways = lateral_testbed(4, 1.0, SlipDefinition::travel, {0.0, 30.0, 60.0, 90.0});
  const auto travel = analysis::study_single_wheel(test::ding_tyii(), sideways.points);
  ASSERT_EQ(travel.other_reading.size(), 1u) << travel.slip_definition_reason;
  EXPECT_EQ(travel.slip_definition, "travel");
  const auto& r = travel.other_reading.front();
  EXPECT_EQ(r.slip_definition, "longitudinal");
  EXPECT_LT(travel.selection.empty() ? travel.baseline_score : travel.selection.back().held_out_score,
            r.selection.empty() ? r.baseline_score : r.selection.back().held_out_score);
  for (const auto* reading : {&r, &travel}) {
    EXPECT_NE(reading->slip_definition_reason.find("does not state its slip definition"), std::string::npos)
        << reading->slip_definition_reason;
    // Each reading's causes and final held-out score are given, to weigh.
    for (const char* part : {"read as longitudinal slip: causes ", "read as travel slip: causes ", " sigma"}) {
      EXPECT_NE(reading->slip_definition_reason.find(part), std::string::npos) << reading->slip_definition_reason;
    }
    EXPECT_FALSE(reading->verdict.empty());
    EXPECT_FALSE(reading->per_wheel.empty());
  }
  for (const auto& w : travel.per_wheel) {
    if (w.quantity == Quantity::lateral_force || w.quantity == Quantity::drawbar_pull) {
      EXPECT_LT(w.model_rmse, 0.8) << w.wheel << ' ' << to_string(w.quantity);
    }
  }
  const auto bed = lateral_testbed(5, 1.0, SlipDefinition::travel, {0.0, 20.0, 40.0, 60.0});
  analysis::DiscrepancyOptions stated;
  stated.slip_definition = SlipDefinition::travel;
  const auto chosen = analysis::study_single_wheel(test::ding_tyii(), bed.points, stated);
  EXPECT_TRUE(chosen.other_reading.empty());
  analysis::DiscrepancyOptions forced;
  forced.slip_definition = SlipDefinition::longitudinal;
  const auto wrong = analysis::study_single_wheel(test::ding_tyii(), bed.points, forced);
  EXPECT_EQ(wrong.slip_definition_reason, "given");
  const double right_fy = held_out_of(
      chosen, chosen.selection.empty() ? chosen.baseline_held_out_rmse : chosen.selection.back().held_out_rmse,
      Quantity::lateral_force);
  const double wrong_fy =
      held_out_of(wrong, wrong.selection.empty() ? wrong.baseline_held_out_rmse : wrong.selection.back().held_out_rmse,
                  Quantity::lateral_force);
  EXPECT_LT(right_fy, 0.8);
  EXPECT_GT(wrong_fy, 3.0 * right_fy);
}

// Longitudinal (Ishigami) slip with a wheel dragged almost sideways (87 deg
// at s = 0.1: read longitudinally it slides at 17 times its rim speed). A
// rule "that can only be a travel slip" read it as travel and claimed three
// causes; fitting both readings keeps the longitudinal one and no cause.
TEST(SlipDefinition, AWheelDraggedSidewaysAtALongitudinalSlipIsNotReadAsTravel) {
  const auto bed = lateral_testbed(6, 1.0, SlipDefinition::longitudinal, {0.0, 30.0, 60.0, 87.0});
  Soil soil = test::ding_tyii();
  soil.lateral_shear_modulus = bed.k_y;  // the testbed's soil: nothing hidden but the reading
  const auto r = analysis::study_single_wheel(soil, bed.points);
  EXPECT_EQ(r.slip_definition, "longitudinal") << r.slip_definition_reason;
  EXPECT_TRUE(r.selection.empty()) << r.verdict;
  for (const auto& w : r.per_wheel) EXPECT_LT(w.model_rmse, w.quantity == Quantity::sinkage ? 8e-4 : 0.8) << w.wheel;
}

// Straight-driving data: the lateral candidates do not apply.
TEST(LateralCandidates, NeedPointsAtASlipAngle) {
  const auto points = testbed(pick_effect(1, true), 1, analysis::DiscrepancyOptions{}.sigma);
  const auto r = analysis::study_single_wheel(test::ding_tyii(), points);
  EXPECT_EQ(r.baseline_model, "Wong-Reece");
  for (const char* name : {"lateral-shear-modulus", "sidewall"}) {
    const auto* c = candidate_named(r, name);
    ASSERT_NE(c, nullptr) << name;
    EXPECT_FALSE(c->applicable) << name;
  }
}

// Calibration of the lateral shear modulus's +-1 sigma on simulated truth
// (seeds 3000-; ROVERLAB_CALIBRATION_SEEDS for more): its intervals cover
// the hidden k_y about as often as they say.
TEST(LateralCalibration, TheLateralShearModulusIntervalCoversTheHiddenValue) {
  const unsigned n = test::calibration_seeds(8);
  unsigned within1 = 0, within2 = 0, count = 0;
  // The testbed's slip reading given: this measures k_y's interval, not the
  // reading's choice (SlipDefinition.*), and halves the cost.
  analysis::DiscrepancyOptions longitudinal;
  longitudinal.slip_definition = SlipDefinition::longitudinal;
  for (unsigned seed = 3000; seed < 3000 + n; ++seed) {
    const auto bed = lateral_testbed(seed);
    const auto r = analysis::study_single_wheel(test::ding_tyii(), bed.points, longitudinal);
    const auto* c = candidate_named(r, "lateral-shear-modulus");
    if (c == nullptr || c->fit.parameters.empty() || !std::isfinite(c->fit.parameters[0].sigma)) continue;
    const double z = std::abs(c->fit.parameters[0].value - bed.k_y) / c->fit.parameters[0].sigma;
    ++count;
    within1 += z <= 1 ? 1 : 0;
    within2 += z <= 2 ? 1 : 0;
  }
  std::printf("lateral runs: %u, with a sigma: %u, within 1 sigma: %u, within 2 sigma: %u\n", n, count, within1,
              within2);
  ASSERT_EQ(count, n);
  EXPECT_GE(within1, count * 40 / 100);
  EXPECT_LE(within1, count * 90 / 100);
  EXPECT_GE(within2, count * 75 / 100);
}

// A hidden sidewall term three times Hegedus's (k_y still hidden as above):
// forward selection names both lateral causes.
TEST(LateralHiddenEffect, ALargerSidewallTermIsNamedWithTheShearModulus) {
  const auto bed = lateral_testbed(2, 3.0);
  const auto r = analysis::study_single_wheel(test::ding_tyii(), bed.points);
  ASSERT_FALSE(r.selection.empty()) << r.verdict;
  EXPECT_TRUE(named_in_chain(r, "sidewall")) << r.verdict;
  EXPECT_TRUE(named_in_chain(r, "lateral-shear-modulus")) << r.verdict;
  for (const auto& p : r.selection.back().fit.parameters) {
    if (p.parameter == Parameter::sidewall_scale) {
      EXPECT_LT(std::abs(p.value - 3.0), 3.0 * p.sigma) << p.value << " +- " << p.sigma;
    }
  }
}

// Issue 43: a parameter whose fit stops at (or within 1 % of) a bound of its
// search is printed "at its bound" with no sigma, and its candidate is not
// named. A bulldozing term 14 times the nominal one is beyond the scale's 10.
TEST(SingleWheelVerdict, AParameterAtItsBoundHasNoSigmaAndNamesNoCause) {
  Hidden h;
  h.effect = "bulldozing";
  h.parameter = Parameter::bulldozing_scale;
  h.value = 14.0;
  h.model.extensions.bulldozing = true;
  h.model.extensions.bulldozing_scale = h.value;
  const analysis::DiscrepancyOptions options;
  const auto points = testbed(h, 5, options.sigma);
  const analysis::DiscrepancyReport r = analysis::study_single_wheel(test::ding_tyii(), points, options);
  bool any = false;
  for (const auto& c : r.candidates) {
    for (const auto& p : c.fit.parameters) {
      if (!p.at_bound) continue;
      any = true;
      EXPECT_TRUE(std::isnan(p.sigma)) << c.name << " " << to_string(p.parameter);
    }
  }
  EXPECT_TRUE(any) << r.verdict;
  for (const auto& s : r.selection) {
    for (const auto& p : s.fit.parameters) EXPECT_FALSE(p.at_bound) << s.name << ": " << r.verdict;
  }
  EXPECT_EQ(r.verdict.find("Cause: bulldozing"), std::string::npos) << r.verdict;
  EXPECT_EQ(r.verdict.find("+- 0"), std::string::npos) << r.verdict;
}

// Issue 43: each step of the forward selection carries its share of the
// held-out gain (the shares add up to the whole gain), and a named step
// takes at least kNegligibleGainShare of it and cuts some quantity's
// held-out RMSE by 30 %: the verdict never names a step its per-quantity
// sentences say explains nothing.
TEST(SingleWheelVerdict, ANamedStepCarriesItsShareAndExplainsAQuantity) {
  for (unsigned seed : {31u, 32u}) {
    Hidden h;
    h.model.extensions.slip_sinkage_n1 = 0.4;
    h.model.extensions.grousers = true;
    h.model.extensions.grouser_effectiveness = 0.7;
    const analysis::DiscrepancyOptions options;
    const auto r = analysis::study_single_wheel(test::ding_tyii(), testbed(h, seed, options.sigma), options);
    ASSERT_FALSE(r.selection.empty()) << r.verdict;
    double total = 0;
    for (const auto& s : r.selection) total += s.gain_share;
    EXPECT_NEAR(total, 1.0, 1e-9) << r.verdict;
    for (const auto& s : r.selection) {
      if (s.role != analysis::StepRole::cause) continue;
      EXPECT_GE(s.gain_share, analysis::kNegligibleGainShare) << s.name;
      const std::string last = test::last_step(s.name);
      const bool explains = std::any_of(r.quantity_verdicts.begin(), r.quantity_verdicts.end(),
                                        [&](const analysis::QuantityVerdict& v) { return v.explained_by == last; });
      EXPECT_TRUE(explains) << last << ": " << r.verdict;
    }
  }
}

// Issue 47 F20: the progress follows the work. It was 0 % through the screen
// (a study of 100,000 points showed nothing for minutes), then 50 % at once,
// then a few steps. Each report's fraction stays near the share of the run's
// time gone, and none jumps.
TEST(StudyProgress, GrowsWithTheWorkWithoutJumps) {
  const analysis::DiscrepancyOptions defaults;
  const auto points = testbed(pick_effect(3, false), 3, defaults.sigma);
  struct Mark {
    double seconds, fraction;
  };
  std::vector<Mark> marks;
  const auto start = std::chrono::steady_clock::now();
  const auto since = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(); };
  analysis::DiscrepancyOptions options;
  options.progress = [&](double f) { marks.push_back({since(), f}); };
  // On one thread: with more, the fits other threads finish are reported with the caller's next
  // one (a step of several fits at once), which depends on scheduling, not on the weights.
  set_thread_count(1);
  (void)analysis::study_single_wheel(test::ding_tyii(), points, options);
  set_thread_count(default_thread_count());
  const double total = since();
  ASSERT_GE(marks.size(), 20U);
  EXPECT_EQ(marks.back().fraction, 1.0);
  double most_behind = 0.0, most_ahead = 0.0, largest_step = marks.front().fraction;
  for (std::size_t k = 0; k < marks.size(); ++k) {
    // Steps while the study works; the last report (1.0, the study done) may jump from an
    // estimate that expected more selection steps than were taken: `most_behind` bounds that.
    if (k > 0 && k + 1 < marks.size()) {
      ASSERT_GE(marks[k].fraction, marks[k - 1].fraction) << k;
      largest_step = std::max(largest_step, marks[k].fraction - marks[k - 1].fraction);
    }
    const double share = marks[k].seconds / total;
    most_behind = std::max(most_behind, share - marks[k].fraction);
    most_ahead = std::max(most_ahead, marks[k].fraction - share);
  }
  EXPECT_LT(largest_step, 0.25);
  // Measured 0.30-0.32 on one thread, idle (the weights undercount the later selection steps: issue 47,
  // F20 is not fully fixed); 0.4 leaves room for a loaded machine.
  EXPECT_LT(most_behind, 0.4) << "the progress lags the time";
  EXPECT_LT(most_ahead, 0.35) << "the progress runs ahead of the time";
  std::printf("progress: %zu reports over %.1f s, largest step %.2f, behind %.2f, ahead %.2f\n", marks.size(), total,
              largest_step, most_behind, most_ahead);
}

// Issue 43 item 4: the negligible-share threshold (kNegligibleGainShare)
// calibrated on simulated truth. Runs with one hidden effect, and with two,
// of each of seven extensions at sizes from the tests' pools down to a tenth
// of them (barely detectable): every step the forward selection takes is
// recorded with its share of the held-out gain, whether it cut a quantity's
// held-out RMSE by 30 %, and its role (docs/validation/discrepancy.md, "A
// cause that matters"; ROVERLAB_CALIBRATION_SEEDS runs per kind).
namespace {

struct TrueEffect {
  const char* candidate;
  Parameter parameter;
  double neutral;  // the value that changes nothing (NaN: the soil's own)
  double pool;     // a value inside the hidden-effect tests' pools
};

const TrueEffect kTrueEffects[] = {
    {"slip-sinkage", Parameter::slip_sinkage_n1, 0.0, 0.4},
    {"grousers", Parameter::grouser_effectiveness, 0.0, 0.7},
    {"soil-strength", Parameter::soil_strength, 1.0, 0.7},
    {"bulldozing", Parameter::bulldozing_scale, 0.0, 2.0},
    {"slip-shear-modulus", Parameter::shear_modulus_slip, 0.0, 2.5},
    {"rear-angle", Parameter::rear_angle_ratio, 0.0, 0.3},
    {"max-stress-angle", Parameter::c2, NAN, 0.05},
};
constexpr unsigned kTrueEffectCount = sizeof kTrueEffects / sizeof kTrueEffects[0];
constexpr double kSizes[] = {1.0, 0.5, 0.25, 0.1};  // fraction of the way from neutral to the pool's value

// The testbed's points generated with the given effects at the given sizes.
std::vector<WheelTestPoint> effects_testbed(const std::vector<std::pair<const TrueEffect*, double>>& effects,
                                            unsigned seed) {
  Soil soil = test::ding_tyii();
  ModelOptions model;
  for (const auto& [e, size] : effects) {
    for (const auto& c : analysis::single_wheel_candidates()) {
      if (c->name() == std::string(e->candidate)) c->configure(model.extensions);
    }
    const double neutral = std::isnan(e->neutral) ? get_parameter(soil, model.extensions, e->parameter) : e->neutral;
    set_parameter(soil, model.extensions, e->parameter, neutral + size * (e->pool - neutral));
  }
  const analysis::DiscrepancyOptions options;
  std::mt19937 rng(seed);
  std::normal_distribution<double> unit(0.0, 1.0);
  auto points = testbed(Hidden{}, seed, options.sigma);
  for (auto& p : points) {
    const Traction t = evaluate(soil, p.wheel, p.load, p.slip, model);
    p.drawbar_pull = t.drawbar_pull + options.sigma.drawbar_pull * unit(rng);
    p.torque = t.resistive_torque + options.sigma.torque * unit(rng);
    p.sinkage = t.sinkage + options.sigma.sinkage * unit(rng);
  }
  return points;
}

std::string size_text(double size) {
  char text[16];
  std::snprintf(text, sizeof text, "x%g", size);
  return text;
}

}  // namespace

TEST(Calibration, NegligibleShareSeparatesHiddenEffectsFromStandIns) {
  const unsigned n = test::calibration_seeds(1);
  std::vector<test::StepShare> steps;
  unsigned one_effect_runs = 0, named_alone = 0;
  for (unsigned k = 0; k < n; ++k) {
    // One effect: each of them at a size chosen by the run (all four sizes over four runs).
    for (unsigned e = 0; e < kTrueEffectCount; ++e) {
      const unsigned seed = 4000 + 10 * k + e;
      const double size = kSizes[(k + e) % 4];
      const TrueEffect& t = kTrueEffects[e];
      const auto r = analysis::study_single_wheel(test::ding_tyii(), effects_testbed({{&t, size}}, seed));
      test::record_steps(r, std::string(t.candidate) + " " + size_text(size) + " seed " + std::to_string(seed),
                         {t.candidate}, steps);
      ++one_effect_runs;
      const auto its_step = [&](const std::string& name) { return name.find(t.candidate) != std::string::npos; };
      named_alone += test::names_exactly(r, its_step) ? 1 : 0;
    }
    // Two effects: pairs of different effects, sizes from the pool down to a quarter.
    for (unsigned e = 0; e < 3; ++e) {
      const unsigned seed = 5000 + 10 * k + e;
      const unsigned a = (3 * k + e) % kTrueEffectCount,
                     b = (a + 1 + (k + e) % (kTrueEffectCount - 1)) % kTrueEffectCount;
      const double size_a = kSizes[k % 3], size_b = kSizes[(k + e) % 3];
      const auto r = analysis::study_single_wheel(
          test::ding_tyii(), effects_testbed({{&kTrueEffects[a], size_a}, {&kTrueEffects[b], size_b}}, seed));
      test::record_steps(r,
                         std::string(kTrueEffects[a].candidate) + " " + size_text(size_a) + " + " +
                             kTrueEffects[b].candidate + " " + size_text(size_b) + " seed " + std::to_string(seed),
                         {kTrueEffects[a].candidate, kTrueEffects[b].candidate}, steps);
    }
  }
  const auto c = test::report_step_shares("single wheel", steps, one_effect_runs, named_alone);
  EXPECT_EQ(c.true_one_under, 0U);
  EXPECT_LE(c.true_two_under, c.true_two / 20);
}
