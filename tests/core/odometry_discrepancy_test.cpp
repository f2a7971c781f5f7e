// The odometry discrepancy study finds effects hidden in simulated skid-steer
// drives (recorded only in the log's truth metadata) and stays quiet when
// there is none.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "core/common/error.h"
#include "core/discrepancy/odometry/candidates.h"
#include "core/discrepancy/odometry/study.h"
#include "core/simulation/skid_steer_scenario.h"
#include "tests/support/calibration_seeds.h"
#include "tests/support/step_shares.h"

using namespace roverlab;

namespace {

analysis::OdometryDiscrepancyReport study(const std::string& effect, double value, unsigned seed) {
  simulation::SkidSteerScenario s = simulation::default_slip_scenario(seed);
  simulation::set_effect(s, "slip", 0.0);  // firm ground: the hidden effect is the only error
  if (!effect.empty()) simulation::set_effect(s, effect, value);
  return analysis::study_odometry(simulation::simulate_skid_steer(s));
}

const analysis::OdometryCandidate& named(const analysis::OdometryDiscrepancyReport& r) {
  return r.candidates.at(static_cast<std::size_t>(r.best));
}

double parameter(const analysis::OdometryCandidate& c, const std::string& name) {
  for (const auto& p : c.parameters) {
    if (p.name == name) return p.value;
  }
  ADD_FAILURE() << "no parameter " << name;
  return NAN;
}

}  // namespace

TEST(OdometryDiscrepancy, FindsSkidSteerTurning) {
  for (unsigned seed : {1u, 2u}) {
    const auto r = study("turning-track-factor", 1.8, seed);
    ASSERT_GE(r.best, 0) << r.verdict;
    EXPECT_EQ(named(r).name, "turning track") << r.verdict;
    EXPECT_NEAR(parameter(named(r), "track_factor"), 1.8, 0.05);
    EXPECT_LT(named(r).held_out_rmse, 0.2 * r.baseline_held_out_rmse);
  }
}

TEST(OdometryDiscrepancy, FindsOneSideRollingShort) {
  const auto r = study("left-radius-scale", 0.97, 3);
  ASSERT_GE(r.best, 0) << r.verdict;
  EXPECT_EQ(named(r).name, "per-side scale") << r.verdict;
  EXPECT_NEAR(parameter(named(r), "left_scale"), 0.97, 0.005);
  EXPECT_NEAR(parameter(named(r), "right_scale"), 1.0, 0.005);
}

TEST(OdometryDiscrepancy, FindsAWheelRadiusScaleAndPrefersTheSimplerModel) {
  const auto r = study("radius-scale", 1.05, 4);
  ASSERT_GE(r.best, 0) << r.verdict;
  EXPECT_EQ(named(r).name, "radius scale") << r.verdict;
  EXPECT_NEAR(parameter(named(r), "radius_scale"), 1.05, 0.005);
}

TEST(OdometryDiscrepancy, FindsATimeOffsetBetweenStreams) {
  const auto r = study("wheel-time-offset", -1.0, 5);
  ASSERT_GE(r.best, 0) << r.verdict;
  EXPECT_EQ(named(r).name, "time offset") << r.verdict;
  EXPECT_NEAR(parameter(named(r), "time_offset_s"), 1.0, 0.1);  // the correction undoes the offset
}

TEST(OdometryDiscrepancy, NamesNothingWhenNothingIsHidden) {
  for (unsigned seed : {6u, 7u}) {
    const auto r = study("", 0.0, seed);
    EXPECT_EQ(r.best, -1) << r.verdict;
    EXPECT_LT(r.baseline_held_out_rmse, 0.2);
  }
}

TEST(OdometryDiscrepancy, RefusesALogWithoutReference) {
  log::Log lg = simulation::simulate_skid_steer(simulation::default_slip_scenario(1));
  log::Log no_gps;
  for (const auto& s : lg.streams()) {
    if (s.name() != "gps") no_gps.add_stream(s);
  }
  EXPECT_THROW(analysis::study_odometry(no_gps), DataError);
}

TEST(OdometryDiscrepancy, CandidatesComeFromTheRegistryInItsOrder) {
  estimation::WheelSamples fit;
  fit.time = {0.0, 6.0, 12.0};
  fit.left_rate = fit.right_rate = {1.0, 1.0, 1.0};
  const analysis::OdometryStudyOptions options;  // 5 s slip windows
  const auto candidates = analysis::odometry_candidates({fit, 4, options});
  std::vector<std::string> names;
  for (const auto& c : candidates) names.push_back(c->name());
  EXPECT_EQ(names, (std::vector<std::string>{"radius scale", "per-side scale", "turning track", "time offset",
                                             "slip episodes"}));
  // Slip episodes: one slip per window of the fit part, their median on the test part.
  const auto& episodes = *candidates.back();
  ASSERT_EQ(episodes.parameters().size(), 3u);
  const double x[3] = {0.1, 0.4, 0.2};
  EXPECT_EQ(episodes.corrections(x).slip, (std::vector<double>{0.1, 0.4, 0.2}));
  EXPECT_EQ(episodes.held_out_corrections(x).slip, (std::vector<double>(4, 0.2)));
  const auto summary = episodes.summary({0.1, 0.4, 0.2}, {NAN, NAN, NAN});
  ASSERT_EQ(summary.size(), 4u);
  EXPECT_EQ(summary[0].name, "windows");
  EXPECT_EQ(summary[1].value, 0.2);
  // The report lists them in the same order.
  const auto r = study("", 0.0, 1);
  ASSERT_EQ(r.candidates.size(), names.size());
  for (std::size_t i = 0; i < names.size(); ++i) EXPECT_EQ(r.candidates[i].name, names[i]);
}

// Issue 14 item 5: on loops with turns in place both ways of separating a
// wider turning track from one side rolling short are in the data; forward
// selection keeps both, each near its hidden value. On the default drive
// (gentle turns) the nominal-geometry tests above keep one cause each.
TEST(OdometryDiscrepancy, ForwardSelectionKeepsTurningTrackAndPerSideScaleOnLoops) {
  for (unsigned seed : {11u, 12u}) {
    simulation::SkidSteerScenario s = simulation::loop_slip_scenario(seed);
    s.gps_sigma = 0.02;  // the study needs a reference better than the loops' 3 m GPS
    simulation::set_effect(s, "slip", 0.0);
    simulation::set_effect(s, "turning-track-factor", 1.5);
    simulation::set_effect(s, "right-radius-scale", 0.98);
    const analysis::OdometryDiscrepancyReport r = analysis::study_odometry(simulation::simulate_skid_steer(s));
    ASSERT_GE(r.selection.size(), 2u) << seed << ": " << r.verdict;
    const std::string& names = r.selection[1].name;
    EXPECT_NE(names.find("turning track"), std::string::npos) << names;
    EXPECT_NE(names.find("per-side scale"), std::string::npos) << names;
    for (const auto& p : r.selection[1].parameters) {
      if (p.name == "track_factor") {
        EXPECT_NEAR(p.value, 1.5, 0.05) << seed;
      } else if (p.name == "right_scale") {
        EXPECT_NEAR(p.value, 0.98, 0.005) << seed;
      }
    }
    // The pair beats either alone on the held-out half.
    EXPECT_LT(r.selection[1].held_out_rmse, r.selection[0].held_out_rmse) << seed;
    // Both are named, each with its share of the held-out gain (issue 43).
    EXPECT_NE(r.verdict.find("Causes (forward selection)"), std::string::npos) << r.verdict;
    for (const auto& step : r.selection) EXPECT_EQ(step.role, analysis::StepRole::cause) << step.name << r.verdict;
  }
}

// Issue 29: how often the study names a cause on drives without one (target
// at most 5 %), and how often its +-1 / +-2 sigma intervals cover a hidden
// value (targets 60-75 % and 90-98 %), on seeds the other tests do not use.
TEST(OdometryCalibration, FalseClaimsAreRareAndIntervalsCoverTheHiddenValue) {
  const unsigned n = test::calibration_seeds(12);
  unsigned claims = 0, bic_alone = 0;
  for (unsigned seed = 300; seed < 300 + n; ++seed) {
    const auto r = study("", 0.0, seed);
    claims += r.best >= 0 ? 1 : 0;
    bool any = false;
    for (const auto& c : r.candidates) any = any || c.delta_bic < -10.0;
    bic_alone += any ? 1 : 0;
  }
  struct Hidden {
    const char* effect;
    const char* candidate;
    const char* parameter;
    double lo, hi;
  };
  const Hidden kinds[] = {{"radius-scale", "radius scale", "radius_scale", 1.02, 1.08},
                          {"turning-track-factor", "turning track", "track_factor", 1.3, 2.2},
                          {"left-radius-scale", "per-side scale", "left_scale", 0.95, 0.98}};
  unsigned count = 0, within1 = 0, within2 = 0;
  for (unsigned seed = 400; seed < 400 + 3 * n; ++seed) {
    const Hidden& h = kinds[seed % 3];
    const double v = h.lo + (h.hi - h.lo) * ((seed * 37) % 100) / 100.0;
    const auto r = study(h.effect, v, seed);
    if (r.best < 0 || named(r).name != h.candidate) continue;
    for (const auto& p : named(r).parameters) {
      if (p.name != h.parameter || !std::isfinite(p.sigma)) continue;
      const double z = std::abs(p.value - v) / p.sigma;
      ++count;
      within1 += z <= 1 ? 1 : 0;
      within2 += z <= 2 ? 1 : 0;
    }
  }
  std::printf(
      "no-effect drives: %u, claims: %u, BIC alone below -10: %u; hidden: %u, named with a sigma: %u, "
      "within 1 sigma: %u, within 2 sigma: %u\n",
      n, claims, bic_alone, 3 * n, count, within1, within2);
  EXPECT_LE(claims, n / 20);
  ASSERT_GE(count, 3 * n * 3 / 4);
  EXPECT_GE(within2, count * 80 / 100);
}

// Issue 43: a correction whose fit stops at (or within 1 % of) a bound of its
// search is a fact about the search: printed "at its bound" with no sigma,
// and never the named cause. Wheels 60 % larger than nominal are beyond the
// radius scale's 1.5.
TEST(OdometryVerdict, ACorrectionAtItsBoundIsNotNamedAndHasNoSigma) {
  const auto r = study("radius-scale", 1.6, 4);
  bool any = false;
  for (const auto& c : r.candidates) {
    for (const auto& p : c.parameters) {
      if (!p.at_bound) continue;
      any = true;
      EXPECT_TRUE(std::isnan(p.sigma)) << c.name << " " << p.name;
      EXPECT_FALSE(c.significant) << c.name;
    }
  }
  EXPECT_TRUE(any) << r.verdict;
  if (r.best >= 0) {
    EXPECT_TRUE(named(r).at_bound.empty()) << r.verdict;
  }
  for (const auto& s : r.selection) EXPECT_TRUE(s.at_bound.empty()) << s.name;
  EXPECT_EQ(r.verdict.find("Cause: radius scale"), std::string::npos) << r.verdict;
}

// Issue 43: every step of the forward selection carries its share of the
// held-out gain; the shares of a chain add up to the whole gain, and only a
// step with a share of kNegligibleGainShare or more is named.
TEST(OdometryVerdict, EachStepCarriesItsShareOfTheHeldOutGain) {
  const auto r = study("radius-scale", 1.05, 4);
  ASSERT_FALSE(r.selection.empty()) << r.verdict;
  double total = 0;
  for (const auto& s : r.selection) {
    ASSERT_TRUE(std::isfinite(s.gain_share)) << s.name;
    total += s.gain_share;
    EXPECT_EQ(s.role == analysis::StepRole::cause, s.gain_share >= analysis::kNegligibleGainShare) << s.name;
  }
  EXPECT_NEAR(total, 1.0, 1e-9);
  EXPECT_EQ(r.selection.front().role, analysis::StepRole::cause) << r.verdict;
}

// Issue 43 item 4: the negligible-share threshold (kNegligibleGainShare)
// calibrated on simulated truth. Drives on firm ground with one hidden
// effect, and with two, at sizes from the pools above down to a tenth of
// them (barely detectable): every step the forward selection takes is
// recorded with its share of the held-out gain and its role
// (docs/validation/discrepancy.md, "A cause that matters";
// ROVERLAB_CALIBRATION_SEEDS runs per kind).
namespace {

struct OdometryEffect {
  const char* effect;
  double neutral, pool;            // the value that changes nothing; one inside the pools above
  std::vector<const char*> names;  // the candidates whose model holds it
};

const OdometryEffect kOdometryEffects[] = {
    {"radius-scale", 1.0, 1.05, {"radius scale", "per-side scale"}},
    {"left-radius-scale", 1.0, 0.965, {"per-side scale"}},
    {"turning-track-factor", 1.0, 1.75, {"turning track"}},
    {"wheel-time-offset", 0.0, -1.0, {"time offset"}},
};
constexpr double kOdometrySizes[] = {1.0, 0.5, 0.25, 0.1};

// The selection's steps: a step is true when its candidate holds a hidden
// effect that no earlier step holds.
void record_odometry_steps(const analysis::OdometryDiscrepancyReport& r, const std::string& run,
                           const std::vector<const OdometryEffect*>& hidden, std::vector<test::StepShare>& out) {
  std::vector<const OdometryEffect*> accounted;
  for (const auto& s : r.selection) {
    test::StepShare rec;
    rec.run = run;
    rec.step = test::last_step(s.name);
    rec.effects = static_cast<int>(hidden.size());
    for (const OdometryEffect* h : hidden) {
      const bool holds = std::find(h->names.begin(), h->names.end(), rec.step) != h->names.end();
      if (!holds || std::find(accounted.begin(), accounted.end(), h) != accounted.end()) continue;
      rec.truth = true;
      accounted.push_back(h);
    }
    rec.share = s.gain_share;
    rec.role = s.role;
    out.push_back(rec);
  }
}

std::string effect_text(const OdometryEffect& e, double size) {
  char text[64];
  std::snprintf(text, sizeof text, "%s x%g", e.effect, size);
  return text;
}

}  // namespace

TEST(OdometryCalibration, NegligibleShareSeparatesHiddenEffectsFromStandIns) {
  const unsigned n = test::calibration_seeds(2);
  constexpr unsigned kinds = sizeof kOdometryEffects / sizeof kOdometryEffects[0];
  std::vector<test::StepShare> steps;
  unsigned one_effect_runs = 0, named_alone = 0;
  for (unsigned k = 0; k < n; ++k) {
    for (unsigned e = 0; e < kinds; ++e) {
      const unsigned seed = 500 + 10 * k + e;
      const OdometryEffect& h = kOdometryEffects[e];
      const double size = kOdometrySizes[(k + e) % 4];
      const auto r = study(h.effect, h.neutral + size * (h.pool - h.neutral), seed);
      record_odometry_steps(r, effect_text(h, size) + " seed " + std::to_string(seed), {&h}, steps);
      ++one_effect_runs;
      const auto its_step = [&](const std::string& name) {
        return std::find(h.names.begin(), h.names.end(), test::last_step(name)) != h.names.end();
      };
      named_alone += test::names_exactly(r, its_step) ? 1 : 0;
    }
    // Two effects: the time offset with each of the others, sizes from the pool down to a quarter.
    for (unsigned e = 0; e + 1 < kinds; ++e) {
      const unsigned seed = 600 + 10 * k + e;
      const OdometryEffect &a = kOdometryEffects[e], &b = kOdometryEffects[kinds - 1];
      const double size_a = kOdometrySizes[k % 3], size_b = kOdometrySizes[(k + e + 1) % 3];
      simulation::SkidSteerScenario s = simulation::default_slip_scenario(seed);
      simulation::set_effect(s, "slip", 0.0);
      simulation::set_effect(s, a.effect, a.neutral + size_a * (a.pool - a.neutral));
      simulation::set_effect(s, b.effect, b.neutral + size_b * (b.pool - b.neutral));
      const auto r = analysis::study_odometry(simulation::simulate_skid_steer(s));
      record_odometry_steps(r,
                            effect_text(a, size_a) + " + " + effect_text(b, size_b) + " seed " + std::to_string(seed),
                            {&a, &b}, steps);
    }
  }
  const auto c = test::report_step_shares("odometry", steps, one_effect_runs, named_alone);
  EXPECT_EQ(c.true_one_under, 0U);
  EXPECT_LE(c.true_two_under, c.true_two / 20);
}
