// The single-wheel study within the RFT family (issue 43, item 3): on
// RFT-generated points with one hidden change it names that change alone
// within 2 sigma, and it makes no claim without one; the family comparison
// takes RFT on RFT data.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include "core/discrepancy/single_wheel/study.h"
#include "core/terramechanics/rft.h"
#include "tests/support/calibration_seeds.h"
#include "tests/support/step_shares.h"

namespace {

using namespace roverlab;
using namespace roverlab::terramechanics;

constexpr double kPi = 3.14159265358979323846;

Soil described_sand() {
  Soil s;  // the Wong-Reece values of dry_sand (resources/soils), zeta started 2x off
  s.name = "dry_sand";
  s.n = 1.1;
  s.cohesion = 1040;
  s.friction_angle = 28.0 * kPi / 180.0;
  s.shear_modulus = 0.0175;
  s.kc = 990;
  s.kphi = 1528430;
  s.density = 1600;
  s.rft_scale = 1.0e6;
  return s;
}

// A smooth wheel (r 62.5 mm, b 60 mm) at 20 N, travel slips and slip angles
// 0-90 deg, from the RFT model with `truth`'s extensions and zeta 2e6, plus
// noise of the study's stated sigmas.
std::vector<WheelTestPoint> rft_points(const Extensions& truth, unsigned seed) {
  Soil soil = described_sand();
  soil.rft_scale = 2.0e6;
  ModelOptions o;
  o.kind = ModelKind::rft;
  o.slip_definition = SlipDefinition::travel;
  o.extensions = truth;
  std::mt19937 rng(seed);
  std::normal_distribution<double> n(0.0, 1.0);
  const MeasurementSigma sigma;
  std::vector<WheelTestPoint> points;
  for (double slip : {-0.5, 0.0, 0.3, 0.7}) {
    for (double deg : {0.0, 30.0, 60.0, 90.0}) {
      WheelTestPoint p;
      p.wheel = Wheel{0.0625, 0.06, 0, 0.0};
      p.wheel_label = "smooth";
      p.load = 20.0;
      p.slip = slip;
      p.slip_angle = deg * kPi / 180.0;
      const auto t = evaluate_slip_angle(soil, p.wheel, p.load, slip, p.slip_angle, o);
      if (!t.ok()) continue;
      p.drawbar_pull = t.drawbar_pull + sigma.drawbar_pull * n(rng);
      p.lateral_force = t.lateral_force + sigma.lateral_force * n(rng);
      p.sinkage = t.sinkage + sigma.sinkage * n(rng);
      points.push_back(p);
    }
  }
  return points;
}

analysis::DiscrepancyOptions rft_study() {
  analysis::DiscrepancyOptions o;
  o.baseline.kind = ModelKind::rft;
  o.slip_definition = SlipDefinition::travel;
  return o;
}

TEST(RftStudy, AHiddenPileUpIsNamedAloneWithinTwoSigma) {
  Extensions truth;
  truth.rft_pileup = 0.5;
  const auto r = analysis::study_single_wheel(described_sand(), rft_points(truth, 43), rft_study());
  ASSERT_EQ(r.selection.size(), 1u) << r.verdict;
  EXPECT_EQ(r.selection[0].name, "pile-up");
  bool found = false;
  for (const auto& p : r.selection[0].fit.parameters) {
    if (p.parameter == Parameter::rft_pileup) {
      found = true;
      EXPECT_LT(std::abs(p.value - 0.5), 2.0 * p.sigma) << p.value << " +- " << p.sigma;
    }
    if (p.parameter == Parameter::rft_scale) {
      EXPECT_LT(std::abs(p.value - 2.0e6), 2.0 * p.sigma) << p.value;
    }
  }
  EXPECT_TRUE(found);
  EXPECT_EQ(r.baseline_model, "RFT");
}

TEST(RftStudy, NoHiddenChangeNoClaimAndTheMaterialScaleIsFound) {
  const auto r = analysis::study_single_wheel(described_sand(), rft_points({}, 44), rft_study());
  EXPECT_TRUE(r.selection.empty()) << r.verdict;
  ASSERT_EQ(r.families.size(), 1u);
  ASSERT_EQ(r.families[0].parameters.size(), 1u);
  const auto& zeta = r.families[0].parameters[0];
  EXPECT_LT(std::abs(zeta.value - 2.0e6), 2.0 * zeta.sigma) << zeta.value << " +- " << zeta.sigma;
  // Wong-Reece's candidates are not RFT's.
  for (const auto& c : r.candidates) {
    if (c.name == "slip-sinkage") {
      EXPECT_FALSE(c.applicable);
    }
  }
}

TEST(RftStudy, TheFamilyComparisonTakesRftOnRftData) {
  analysis::DiscrepancyOptions o = rft_study();
  o.baseline.kind = ModelKind::wong_reece;
  o.compare_families = true;
  const auto r = analysis::study_single_wheel(described_sand(), rft_points({}, 45), o);
  ASSERT_EQ(r.families.size(), 2u);
  EXPECT_EQ(r.baseline_model, "RFT") << r.family_choice;
  EXPECT_LT(r.families[1].held_out_score, r.families[0].held_out_score);
  // RFT's final model fits within the stated noise: Ishigami is not extended, and the sentence says so.
  EXPECT_LE(r.families[1].final_held_out_score, 1.0);
  EXPECT_NE(r.family_choice.find("within the stated noise, so Ishigami (slip angle) was not extended"),
            std::string::npos)
      << r.family_choice;
}

// A wheel dragged sideways through sand that piles up (pile-up 2.5: |F_y|
// near 2 W at 90 deg, as in real tests): RFT's baseline loses to Ishigami's,
// but RFT with the pile-up wins by far once each family is extended, so the
// family is chosen on the final models, and the pile-up is found.
TEST(RftStudy, AFamilyWhoseBaselineLosesIsTakenWhenItsFinalModelWins) {
  Extensions truth;
  truth.rft_pileup = 2.5;
  analysis::DiscrepancyOptions o = rft_study();
  o.baseline.kind = ModelKind::wong_reece;
  o.compare_families = true;
  const auto r = analysis::study_single_wheel(described_sand(), rft_points(truth, 46), o);
  ASSERT_EQ(r.families.size(), 2u);
  EXPECT_GT(r.families[1].held_out_score, r.families[0].held_out_score) << r.family_choice;  // baselines
  EXPECT_LT(r.families[1].final_held_out_score, 0.5 * r.families[0].final_held_out_score) << r.family_choice;
  EXPECT_EQ(r.baseline_model, "RFT") << r.family_choice;
  ASSERT_EQ(r.selection.size(), 1u) << r.verdict;
  EXPECT_EQ(r.selection[0].name, "pile-up");
  for (const auto& p : r.selection[0].fit.parameters) {
    if (p.parameter == Parameter::rft_pileup) {
      EXPECT_FALSE(p.at_bound);
      EXPECT_LT(std::abs(p.value - 2.5), 2.0 * p.sigma) << p.value << " +- " << p.sigma;
    }
  }
  // Screened on a subset first (family_screen_points under the file's
  // points), the winning family still passes and is studied on all points.
  o.family_screen_points = 20;
  const auto screened = analysis::study_single_wheel(described_sand(), rft_points(truth, 46), o);
  EXPECT_EQ(screened.baseline_model, "RFT") << screened.family_choice;
  ASSERT_EQ(screened.families.size(), 2u);
  EXPECT_EQ(screened.families[1].studied_points, 0u) << screened.family_choice;
  EXPECT_EQ(screened.final_model, r.final_model);
  EXPECT_EQ(screened.family_choice, r.family_choice);
}

// Issue 43 item 4: the negligible-share threshold (kNegligibleGainShare)
// calibrated on simulated truth, within the RFT family: a hidden pile-up or
// depth-dependent scale alone, at sizes from the tests' values (0.5, 1) down
// to a tenth, and both at once; every step the forward selection takes with
// its share and role (docs/validation/discrepancy.md, "A cause that
// matters"; ROVERLAB_CALIBRATION_SEEDS runs per kind).
TEST(RftCalibration, NegligibleShareSeparatesHiddenEffectsFromStandIns) {
  const unsigned n = roverlab::test::calibration_seeds(2);
  constexpr double sizes[] = {1.0, 0.5, 0.25, 0.1};
  std::vector<roverlab::test::StepShare> steps;
  const auto record = [&](const analysis::DiscrepancyReport& r, const std::string& run,
                          const std::vector<std::string>& hidden) {
    roverlab::test::record_steps(r, run, hidden, steps);
  };
  for (unsigned k = 0; k < n; ++k) {
    for (unsigned e = 0; e < 4; ++e) {
      const unsigned seed = 4300 + 10 * k + e;
      const double size = sizes[(k + e) % 4];
      Extensions truth;
      const bool pile = e % 2 == 0;
      (pile ? truth.rft_pileup : truth.rft_depth_scale) = size * (pile ? 0.5 : 1.0);
      char run[96];
      std::snprintf(run, sizeof run, "%s x%g seed %u", pile ? "pile-up" : "depth-scale", size, seed);
      record(analysis::study_single_wheel(described_sand(), rft_points(truth, seed), rft_study()), run,
             {pile ? "pile-up" : "depth-scale"});
    }
    const unsigned seed = 4400 + k;
    const double a = sizes[k % 3], b = sizes[(k + 1) % 3];
    Extensions both;
    both.rft_pileup = 0.5 * a;
    both.rft_depth_scale = b;
    char run[96];
    std::snprintf(run, sizeof run, "pile-up x%g + depth-scale x%g seed %u", a, b, seed);
    record(analysis::study_single_wheel(described_sand(), rft_points(both, seed), rft_study()), run,
           {"pile-up", "depth-scale"});
  }
  roverlab::test::print_step_shares("single wheel, RFT family", steps);
  // The trade-off at other thresholds, then the calibrated property at
  // kNegligibleGainShare: no hidden effect the selection took in a one-effect
  // run falls under it, nor more than 1 in 20 of the second effects of
  // two-effect runs (measured over 40 seeds: 1 of 214 single-wheel, 2 of 131
  // odometry). Stand-ins are counted, not bounded: most take large shares
  // (they replace a hidden effect in the chain), which no share threshold
  // can tell from a cause (docs/validation/discrepancy.md).
  for (const double threshold : {0.005, 0.02, 0.05, 0.10}) roverlab::test::count_step_shares(steps, threshold);
  const auto c = roverlab::test::count_step_shares(steps, analysis::kNegligibleGainShare);
  EXPECT_EQ(c.true_one_under, 0U);
  EXPECT_LE(c.true_two_under, c.true_two / 20);
}

}  // namespace
