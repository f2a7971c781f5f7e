// The rover discrepancy study (issue 13): hidden effects in a simulated
// planar rocker-bogie log, found again without reading its truth.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "core/common/error.h"
#include "core/discrepancy/likelihood.h"
#include "core/discrepancy/rover/candidates.h"
#include "core/discrepancy/rover/prediction.h"
#include "core/discrepancy/rover/study.h"
#include "core/simulation/random_effects.h"
#include "core/simulation/sensor_effects.h"
#include "importers/soil_file.h"

using namespace roverlab;

namespace {

analysis::RoverScenarioModel flat_model(double seconds) {
  analysis::RoverScenarioModel m;
  m.name = "flat test";
  m.rover = "kapvik_planar";
  m.run.soil = io::load_soil(std::string(ROVERLAB_RESOURCES_DIR) + "/soils/ding_tyii.json");
  m.run.path = simulation::flat_path();
  m.run.duration = seconds;
  return m;
}

log::Log measured(const analysis::RoverScenarioModel& m, const std::vector<std::pair<std::string, double>>& effects,
                  unsigned seed) {
  simulation::RockerBogieRun run = m.run;
  run.seed = seed;
  for (const auto& e : effects) simulation::set_effect(run.effects, e.first, e.second);
  return simulation::simulate_rocker_bogie(m.geometry, m.parameters, run).log;
}

// The named causes (issue 43: a step "also consistent" or "at its bound" is not one).
std::vector<std::string> causes(const analysis::RoverDiscrepancyReport& r) {
  std::vector<std::string> out;
  for (const auto& s : r.selection) {
    if (s.role == analysis::StepRole::cause) out.push_back(s.parameters.front().effect);
  }
  return out;
}

const analysis::RoverParameterFit& fitted(const analysis::RoverDiscrepancyReport& r, const std::string& effect) {
  for (const auto& s : r.selection) {
    for (const auto& p : s.parameters) {
      if (p.effect == effect) return p;
    }
  }
  throw std::runtime_error("not fitted: " + effect);
}

}  // namespace

TEST(RoverDiscrepancy, NoEffectNoCauseAndTheResidualsAreNoise) {
  const auto m = flat_model(20);
  for (unsigned seed : {1U, 2U}) {
    const auto r = analysis::study_rover(measured(m, {}, seed), m);
    EXPECT_TRUE(r.selection.empty()) << r.verdict;
    for (const auto& c : r.channels) {
      if (c.stream != "commands") {
        EXPECT_LT(c.rmse / c.sigma, 1.3) << c.stream << "/" << c.channel;
      }
    }
    for (const auto& c : r.checks) EXPECT_TRUE(c.consistent) << c.name << ": " << c.value;
    EXPECT_NEAR(r.final_held_out, r.baseline_held_out, 1e-12);
  }
}

TEST(RoverDiscrepancy, TheScenariosOwnEffectsArePartOfTheModel) {
  auto m = flat_model(20);
  simulation::set_effect(m.run.effects, "gyro-bias", 0.003);  // a gyro bias the scenario file already states
  simulation::set_effect(m.run.effects, "slip-sinkage", 0.3);
  const auto r = analysis::study_rover(measured(m, {}, 6), m);
  EXPECT_TRUE(r.selection.empty()) << r.verdict;
}

TEST(RoverDiscrepancy, AGyroBiasIsNamedWithItsSizeAndTheCheckWithoutSimulationSeesIt) {
  const auto m = flat_model(20);
  const auto r = analysis::study_rover(measured(m, {{"gyro-bias", 0.003}}, 3), m);
  ASSERT_EQ(causes(r), std::vector<std::string>{"gyro-bias"}) << r.verdict;
  const auto& p = fitted(r, "gyro-bias");
  EXPECT_LT(std::abs(p.value - 0.003), 3 * p.sigma)
      << p.value << " +- " << p.sigma;                                 // one run: 3 sigma; the suite counts 2 sigma
  EXPECT_FALSE(r.checks.front().consistent) << r.checks.front().name;  // pitch rate vs accelerometers
  for (const auto& c : r.checks) {  // a sensor cause leaves the traction on the model's surfaces
    if (c.name.find("net-traction") != std::string::npos) {
      EXPECT_TRUE(c.consistent) << c.name << ": " << c.value;
    }
  }
}

TEST(RoverDiscrepancy, AWeakerSoilFromAPositionIsNamedWithItsStrengthAndPosition) {
  const auto m = flat_model(40);  // long enough for the traction check's mean to see the weaker soil
  const auto r = analysis::study_rover(measured(m, {{"soil-strength", 0.8}, {"effect-start-x", 0.15}}, 4), m);
  ASSERT_EQ(causes(r), std::vector<std::string>{"soil-strength"}) << r.verdict;
  EXPECT_NEAR(fitted(r, "soil-strength").value, 0.8, 0.005);
  EXPECT_NEAR(fitted(r, "effect-start-x").value, 0.15, 0.005);
  EXPECT_LT(r.final_held_out, 0.1 * r.baseline_held_out);  // the gain, on the test blocks
  bool traction_departs = false;                           // the check without simulation sees a physical cause
  for (const auto& c : r.checks)
    traction_departs |= c.name.find("net-traction drawbar") != std::string::npos && !c.consistent;
  EXPECT_TRUE(traction_departs);
}

TEST(RoverDiscrepancy, TwoCausesAtOnceAreBothNamed) {
  const auto m = flat_model(20);
  const auto r = analysis::study_rover(measured(m, {{"slip-sinkage", 0.3}, {"force-offset", 0.4}}, 5), m);
  auto c = causes(r);
  std::sort(c.begin(), c.end());
  EXPECT_EQ(c, (std::vector<std::string>{"force-offset", "slip-sinkage"})) << r.verdict;
  EXPECT_NEAR(fitted(r, "force-offset").value, 0.4, 0.01);
}

TEST(RoverDiscrepancy, ALogItCannotStudyIsRefusedNamingWhy) {
  const auto m = flat_model(20);
  log::Log lg = measured(m, {}, 1);
  analysis::RoverScenarioModel other = m;
  other.rover = "exomars_bb2";
  EXPECT_THROW(analysis::study_rover(lg, other), DataError);  // another rover
  log::Log short_log = measured(flat_model(5), {}, 1);
  try {
    analysis::study_rover(short_log, m);
    FAIL() << "a 5 s log was studied";
  } catch (const DataError& e) {
    EXPECT_NE(std::string(e.what()).find("8 blocks"), std::string::npos) << e.what();
  }
  log::Log no_commands;
  no_commands.metadata = lg.metadata;
  for (const auto& s : lg.streams()) {
    if (s.name() != "commands") no_commands.add_stream(s);
  }
  try {
    analysis::study_rover(no_commands, m);
    FAIL() << "a log without commands was studied";
  } catch (const DataError& e) {
    EXPECT_NE(std::string(e.what()).find("commands"), std::string::npos) << e.what();
  }
}

TEST(RoverDiscrepancy, EveryCandidateFreesEffectsTheSimulatorKnowsWithinItsBounds) {
  analysis::RoverResidualFeatures f;
  f.change_x = 0.3;
  f.hold_start = 10;
  const auto cands = analysis::rover_candidates();
  EXPECT_EQ(cands.size(), 11U);  // with the slip angle (issue 33)
  for (const auto& c : cands) {
    for (const auto& p : c->parameters(f)) {
      simulation::RockerBogieEffects fx;
      EXPECT_NO_THROW(simulation::set_effect(fx, p.effect, p.start)) << c->name();
      EXPECT_NO_THROW(simulation::set_effect(fx, p.effect, p.lower)) << c->name();
      EXPECT_NO_THROW(simulation::set_effect(fx, p.effect, p.upper)) << c->name();
      EXPECT_GT(p.step, 0) << c->name();
    }
  }
}

TEST(RoverDiscrepancy, TheSensorEffectsTheStudyFitsAreTheOnesTheSimulatorInjects) {
  const auto m = flat_model(5);
  simulation::RockerBogieRun run = m.run;
  run.sensor_noise = false;
  const log::Log plain = simulation::simulate_rocker_bogie(m.geometry, m.parameters, run).log;
  for (const auto& e : std::vector<std::pair<std::string, double>>{{"gyro-bias", 0.01},
                                                                   {"force-scale", 1.1},
                                                                   {"force-offset", 2},
                                                                   {"encoder-dropout", 1},
                                                                   {"accel-bias", 0.1}}) {
    run.effects = {};
    simulation::set_effect(run.effects, e.first, e.second);
    const log::Log with = simulation::simulate_rocker_bogie(m.geometry, m.parameters, run).log;
    simulation::SensorSeries s;
    const auto& names = simulation::sensor_channels();
    for (std::size_t c = 0; c < simulation::kSensorChannels; ++c) {
      s.values[c] = plain.stream(names[c].stream).channel(names[c].name).values;
    }
    s.time = plain.stream("joints").time();
    simulation::apply_sensor_effects(run.effects, s);
    for (std::size_t c = 0; c < simulation::kSensorChannels; ++c) {
      EXPECT_EQ(s.values[c], with.stream(names[c].stream).channel(names[c].name).values)
          << e.first << " " << names[c].name;
    }
  }
}

TEST(RandomEffects, TheSeedDrawsNoneOneOrTwoEffectsNeverTwoPhysicalOnes) {
  int counts[3] = {0, 0, 0};
  for (unsigned seed = 1; seed <= 200; ++seed) {
    const auto r = simulation::random_effects(seed, 60, 0.8);
    ASSERT_LE(r.causes.size(), 2U);
    ++counts[r.causes.size()];
    int physical = 0;
    for (const auto& c : r.causes) {
      physical += c == "soil-strength" || c == "slip-sinkage" || c == "grousers" || c == "wheel-radius-scale" ||
                  c == "slip-angle";
    }
    EXPECT_LE(physical, 1) << seed;
    simulation::RockerBogieEffects fx;
    for (const auto& e : r.effects) EXPECT_NO_THROW(simulation::set_effect(fx, e.first, e.second)) << e.first;
    EXPECT_EQ(simulation::random_effects(seed, 60, 0.8).effects, r.effects);  // the seed decides
  }
  for (int c : counts) EXPECT_GT(c, 25);
}

// Issue 33, item 5: a slip angle outside the random pool's 4-30 deg, below
// and above it, is named alone with its size within 2 sigma (the planar side
// sees ~beta^2: the screen starts on a grid, or 45 deg was screened out
// behind a weaker soil and 2 deg not fitted at all).
TEST(RoverDiscrepancy, ASlipAngleOutsideThePoolIsNamedWithItsSize) {
  const auto m = flat_model(60);
  for (const auto& [beta, seed] : {std::pair{2.0, 5U}, std::pair{45.0, 5U}}) {
    const auto r = analysis::study_rover(measured(m, {{"slip-angle", beta}}, seed), m);
    ASSERT_EQ(causes(r), std::vector<std::string>{"slip-angle"}) << r.verdict;
    const auto& p = fitted(r, "slip-angle");
    ASSERT_TRUE(std::isfinite(p.sigma) && p.sigma > 0) << r.verdict;
    // One run: 3 sigma (the suite counts 2; with a calibrated sigma one seed
    // in twenty is beyond 2: seed 5 at 2 deg gives 1.9635 +- 0.018).
    EXPECT_LT(std::abs(p.value - beta), 3 * p.sigma) << p.value << " +- " << p.sigma;
  }
}

// A printed +-1 sigma means its scatter: over ten noise seeds at one slip
// angle the errors sit at an RMS of one sigma. Before the encoders' floor
// fell below their noise and the sigma became block-robust, they sat at
// 0.48 sigma (the suite's 2001-2021: 0.49): the sigma was twice the scatter.
TEST(RoverCalibration, ASlipAnglesSigmaIsItsScatterOverNoiseSeeds) {
  const auto m = flat_model(60);
  double sum_z2 = 0;
  int n = 0;
  for (unsigned seed = 3001; seed <= 3010; ++seed) {
    const auto r = analysis::study_rover(measured(m, {{"slip-angle", 8.0}}, seed), m);
    ASSERT_EQ(causes(r), std::vector<std::string>{"slip-angle"}) << seed << ": " << r.verdict;
    const auto& p = fitted(r, "slip-angle");
    ASSERT_TRUE(std::isfinite(p.sigma) && p.sigma > 0) << seed << ": " << r.verdict;
    const double z = (p.value - 8.0) / p.sigma;
    sum_z2 += z * z;
    ++n;
  }
  // sqrt(chi2_10 / 10) lies in [0.57, 1.44] with 95 % probability.
  const double rms = std::sqrt(sum_z2 / n);
  EXPECT_GT(rms, 0.57);
  EXPECT_LT(rms, 1.44);
}

// Issue 29: a soil stronger over the whole run (outside the random pool,
// which draws weaker soils from a position) is named as the soil, its
// strength within 2 sigma; no delta BIC beyond 1e6 and no sigma of 0.
TEST(RoverDiscrepancy, AStrongerSoilOverTheWholeRunIsNamedAsTheSoil) {
  const auto m = flat_model(60);
  const auto r = analysis::study_rover(measured(m, {{"soil-strength", 1.2}}, 7004), m);
  ASSERT_EQ(causes(r), std::vector<std::string>{"soil-strength"}) << r.verdict;
  const auto& p = fitted(r, "soil-strength");
  ASSERT_TRUE(std::isfinite(p.sigma) && p.sigma > 0) << r.verdict;
  EXPECT_LT(std::abs(p.value - 1.2), 2 * p.sigma) << p.value << " +- " << p.sigma;
  for (const auto& c : r.candidates) {
    EXPECT_LT(std::abs(c.delta_bic), 1e6) << c.name;
    for (const auto& q : c.parameters) EXPECT_FALSE(q.sigma == 0) << c.name << " " << q.effect;
  }
  EXPECT_EQ(r.verdict.find("+- 0 "), std::string::npos) << r.verdict;
}

// Outside the random pool: a soil so weak the rover is stuck (mean slip
// above 0.9). From the nominal strength the fit stopped at the edge where
// the model starts to roll and added two sensor causes to the rest (0.82
// plus an IMU time offset and a force scale for a true 0.5; 1.97 for 0.3).
TEST(RoverDiscrepancy, ASoilSoWeakTheRoverIsStuckIsNamedAloneWithItsStrength) {
  const auto m = flat_model(40);
  for (const double strength : {0.4, 0.55}) {
    const auto r = analysis::study_rover(measured(m, {{"soil-strength", strength}}, 7010), m);
    EXPECT_TRUE(r.slip_regime.stuck) << r.slip_regime.text;
    ASSERT_EQ(causes(r), std::vector<std::string>{"soil-strength"}) << r.verdict;
    const auto& p = fitted(r, "soil-strength");
    ASSERT_TRUE(std::isfinite(p.sigma) && p.sigma > 0) << r.verdict;
    EXPECT_NEAR(p.value, strength, std::max(3 * p.sigma, 0.002)) << p.value << " +- " << p.sigma;
  }
}

// Issue 29: the statistics stay readable on a random-effect run (the report
// of seed 5 printed delta BIC -1.9e11 and sigmas of 0).
TEST(RoverDiscrepancy, ARandomEffectRunsStatisticsMeanWhatTheySay) {
  auto m = flat_model(60);
  log::Log lg = measured(m, {{"accel-bias", -0.014314054027044783}, {"wheel-radius-scale", 1.0313037188990837}}, 5);
  const auto r = analysis::study_rover(lg, m);
  auto c = causes(r);
  std::sort(c.begin(), c.end());
  EXPECT_EQ(c, (std::vector<std::string>{"accel-bias", "wheel-radius-scale"})) << r.verdict;
  for (const auto& k : r.candidates) {
    EXPECT_LT(std::abs(k.delta_bic), 1e6) << k.name;
    for (const auto& q : k.parameters) EXPECT_FALSE(q.sigma == 0) << k.name << " " << q.effect;
  }
  const auto& radius = fitted(r, "wheel-radius-scale");
  EXPECT_LT(std::abs(radius.value - 1.0313037188990837), 3 * radius.sigma) << radius.value << " +- " << radius.sigma;
}

// Issue 29: a step the later causes absorb is dropped (the backward half of
// stepwise selection). Suite seed 216 (grousers and a force scale) named a
// third cause, slip-sinkage 0.00035, that the joint refit had taken to
// nothing.
TEST(RoverDiscrepancy, AStepTheLaterCausesAbsorbIsDropped) {
  const auto m = flat_model(60);
  const auto r = analysis::study_rover(
      measured(m, {{"grousers", 0.021990117591605084}, {"force-scale", 1.0296642655850212}}, 216), m);
  auto c = causes(r);
  std::sort(c.begin(), c.end());
  EXPECT_EQ(c, (std::vector<std::string>{"force-scale", "grousers"})) << r.verdict;
  for (const auto& d : r.dropped) EXPECT_NE(r.verdict.find("Dropped " + d), std::string::npos) << r.verdict;
  const auto& g = fitted(r, "grousers");
  EXPECT_LT(std::abs(g.value - 0.021990117591605084), 3 * g.sigma) << g.value << " +- " << g.sigma;
}

// Suite seeds 104 and 393 (flat_60s): a force offset beside a force scale.
// The force scale fitted alone absorbs the offset in the loads (0.9403 for
// 0.9321), and with the chain held at that value the offset's screen was
// worse than nothing (+80 in BIC), so it was never fitted: the study named
// the scale alone, 319 and 857 of its sigmas off. The candidates of a later
// round are now fitted with the chain free.
TEST(RoverDiscrepancy, ACauseTheFirstOneAbsorbedIsNamedBesideIt) {
  const auto m = flat_model(20);
  const std::vector<std::pair<double, double>> pairs = {{0.3522401910755912, 0.9320776839186383},
                                                        {-0.7626085832021574, 1.086553728647127}};
  unsigned seed = 104;
  for (const auto& [offset, scale] : pairs) {
    const auto r = analysis::study_rover(measured(m, {{"force-offset", offset}, {"force-scale", scale}}, seed), m);
    seed = 393;
    auto c = causes(r);
    std::sort(c.begin(), c.end());
    ASSERT_EQ(c, (std::vector<std::string>{"force-offset", "force-scale"})) << r.verdict;
    for (const auto& [effect, truth] : {std::pair{"force-offset", offset}, std::pair{"force-scale", scale}}) {
      const auto& p = fitted(r, effect);
      EXPECT_LT(std::abs(p.value - truth), 3 * p.sigma) << effect << " " << p.value << " +- " << p.sigma;
    }
    EXPECT_FALSE(r.incomplete) << r.verdict;
    for (const auto& ch : r.channels) EXPECT_LT(ch.held_out_sigmas_after, 1.2) << ch.stream << "/" << ch.channel;
  }
}

// A study that stops with a channel still many noise sigmas off has an
// incomplete model, and the named causes' +-1 sigma assume a complete one:
// the verdict says so (here the second cause is withheld by max_causes = 1).
TEST(RoverDiscrepancy, AnIncompleteModelSaysItsSigmasAreNotConfidenceIntervals) {
  const auto m = flat_model(20);
  analysis::RoverStudyOptions one;
  one.max_causes = 1;
  const auto r = analysis::study_rover(
      measured(m, {{"force-offset", 0.3522401910755912}, {"force-scale", 0.9320776839186383}}, 104), m, one);
  ASSERT_EQ(causes(r), std::vector<std::string>{"force-scale"}) << r.verdict;
  const auto& p = fitted(r, "force-scale");
  EXPECT_GT(std::abs(p.value - 0.9320776839186383), 10 * p.sigma);  // why the sigma cannot be read as one
  EXPECT_TRUE(r.incomplete);
  EXPECT_NE(r.verdict.find("The model is incomplete"), std::string::npos) << r.verdict;
  EXPECT_NE(r.verdict.find("are not confidence intervals"), std::string::npos) << r.verdict;
  double worst = 0;
  for (const auto& ch : r.channels) worst = std::max(worst, ch.held_out_sigmas_after);
  EXPECT_GT(worst, analysis::kIncompleteSigmas);
}

// Issue 43: a value within 1 % of a bound of its search is "at its bound"
// (1 % of the bound's size, at most 1 % of the range, at least 1e-6 of it).
TEST(RoverVerdict, AValueWithinOnePercentOfABoundIsAtItsBoundAndHasNoSigma) {
  EXPECT_TRUE(analysis::near_bound(0.302, 0.3, 5.0));   // 0.67 % above the lower bound
  EXPECT_FALSE(analysis::near_bound(0.31, 0.3, 5.0));   // 3.3 % above it
  EXPECT_TRUE(analysis::near_bound(4.96, 0.3, 5.0));    // 0.8 % under the upper bound
  EXPECT_FALSE(analysis::near_bound(0.35, -500, 500));  // a force offset of 0.35 N is not at 0 or +-500
  EXPECT_TRUE(analysis::near_bound(-496, -500, 500));
  EXPECT_FALSE(analysis::near_bound(27.6, 0, 1e5));  // an encoder dropout at 27.6 s
  EXPECT_TRUE(analysis::near_bound(0.0, 0, 2));
  EXPECT_FALSE(analysis::near_bound(0.05, 0, 2));
  EXPECT_EQ(analysis::format_fitted(0.302, 0.001, "1", true), "0.302 (at its bound)");
  EXPECT_EQ(analysis::format_fitted(0.302, 0.001, "m", false), "0.302 +- 0.001 m");
}

// Issue 43: `simulate flat_60s --seed 9612 --effect slip-sinkage=0.5` was
// explained as soil strength 1.0017 +- 0.0009, then slip-sinkage 0.501, then
// wheel radius 0.9986 +- 0.0008: significant, and physically nothing (the
// last cut the held-out error by 0.09 %). Only slip-sinkage is named now;
// each step carries its share of the held-out gain, the others are "also
// consistent with", and every value is the final joint fit's.
TEST(RoverVerdict, ASlipSinkageIsNamedAloneAndTheStepsWithoutShareAreAlsoConsistent) {
  const auto m = flat_model(60);
  const auto r = analysis::study_rover(measured(m, {{"slip-sinkage", 0.5}}, 9612), m);
  ASSERT_EQ(causes(r), std::vector<std::string>{"slip-sinkage"}) << r.verdict;
  const auto& p = fitted(r, "slip-sinkage");
  EXPECT_LT(std::abs(p.value - 0.5), 3 * p.sigma) << p.value << " +- " << p.sigma;
  double shares = 0;
  for (const auto& s : r.selection) {
    ASSERT_TRUE(std::isfinite(s.gain_share)) << s.name;
    ASSERT_TRUE(std::isfinite(s.channel_share)) << s.name;
    EXPECT_EQ(s.role == analysis::StepRole::cause, s.channel_share >= analysis::kNegligibleChannelShare) << s.name;
    if (s.role == analysis::StepRole::cause) shares += s.gain_share;
    if (s.role == analysis::StepRole::also_consistent) {
      EXPECT_NE(r.verdict.find("Also consistent with "), std::string::npos) << r.verdict;
      EXPECT_EQ(r.verdict.find("then " + s.name), std::string::npos) << r.verdict;
    }
  }
  EXPECT_GT(shares, 0.9) << r.verdict;
  EXPECT_EQ(r.verdict.rfind("Cause: slip-sinkage (", 0), 0U) << r.verdict;
}

// Issue 43's rover done-when (docs/validation/rover-one-effect-issue43.md):
// two one-effect runs that named nothing. A lone gyro bias of 0.002 rad/s
// (seed 7054) was fitted right but improved no channel by the material 0.02
// noise variances, so its channel share stayed 0 and it was only "also
// consistent"; a wheel radius scale of 0.8 (seed 7038) ended on the
// candidate's old bound of 0.8. Both are named alone now, within 2 sigma.
TEST(RoverVerdict, ALoneWeakGyroBiasAndASmallWheelAreNamedAlone) {
  const auto m = flat_model(60);
  const std::pair<const char*, std::pair<double, unsigned>> cases[] = {{"gyro-bias", {-0.002, 7054}},
                                                                       {"wheel-radius-scale", {0.8, 7038}}};
  for (const auto& [effect, size_seed] : cases) {
    const auto r = analysis::study_rover(measured(m, {{effect, size_seed.first}}, size_seed.second), m);
    ASSERT_EQ(causes(r), std::vector<std::string>{effect}) << r.verdict;
    const auto& p = fitted(r, effect);
    EXPECT_FALSE(p.at_bound) << r.verdict;
    EXPECT_LT(std::abs(p.value - size_seed.first), 2.5 * p.sigma) << p.value << " +- " << p.sigma;
  }
}

// Issue 43: a fit that stops at a bound of its search names no cause from
// it. A force sensor reading 8 times the force is beyond the force scale's
// search (0.2-5): whatever the study fits there, no named cause has a
// parameter at its bound, and every parameter at its bound is printed
// without a sigma.
TEST(RoverVerdict, AParameterAtItsBoundIsNoCauseAndHasNoSigma) {
  const auto m = flat_model(20);
  const auto r = analysis::study_rover(measured(m, {{"force-scale", 8.0}}, 11), m);
  bool any = false;
  for (const auto& s : r.selection) {
    for (const auto& q : s.parameters) {
      if (!q.at_bound) continue;
      any = true;
      EXPECT_NE(s.role, analysis::StepRole::cause) << r.verdict;
      EXPECT_TRUE(std::isnan(q.sigma)) << r.verdict;
      EXPECT_NE(r.verdict.find(q.effect + " = " + analysis::format_fitted(q.value, q.sigma, q.unit, true)),
                std::string::npos)
          << r.verdict;
    }
  }
  EXPECT_TRUE(any) << r.verdict;
  for (const auto& c : r.candidates) {
    for (const auto& q : c.parameters) {
      if (q.at_bound) {
        EXPECT_TRUE(std::isnan(q.sigma)) << c.name;
      }
    }
  }
}

// A fork's runs come back to the predictor it was forked from in the order
// the fork used them; the runs it only inherited, which the predictor has let
// go since (its cache full: 64 runs of a short log), do not come back at the
// cost of runs it kept. (Bringing them back made the parallel profile
// sigmas simulate 5 runs again on a 60 s log.)
TEST(RoverPredictor, AnAbsorbedForkBringsBackTheRunsItUsedNotTheOnesThePredictorLetGo) {
  const auto m = flat_model(3);
  const log::Log lg = measured(m, {}, 1);
  analysis::rover::Predictor pr(lg, m, 0.25);
  const auto soil = [](int k) {
    simulation::RockerBogieEffects fx;
    fx.soil_strength = 0.5 + 0.01 * k;
    return fx;
  };
  for (int k = 0; k < 64; ++k) pr.simulate(soil(k));  // full: runs 0..63, 0 the least recently used
  ASSERT_EQ(pr.simulations(), 64);
  analysis::rover::Predictor a = pr.fork(), b = pr.fork();
  a.simulate(soil(100));  // two new runs: the predictor lets runs 0 and 1 go for them
  a.simulate(soil(101));
  b.simulate(soil(5));  // an inherited run, used again
  pr.absorb(a);
  pr.absorb(b);
  EXPECT_EQ(pr.simulations(), 66);
  for (int k : {100, 101, 2, 3, 5, 63}) pr.simulate(soil(k));
  EXPECT_EQ(pr.simulations(), 66) << "a run the predictor kept or took from the fork was simulated again";
  pr.simulate(soil(0));  // let go: simulated again, in place of the least recently used (run 4, as run 5 was used)
  EXPECT_EQ(pr.simulations(), 67);
  pr.simulate(soil(5));
  EXPECT_EQ(pr.simulations(), 67);
  pr.simulate(soil(4));
  EXPECT_EQ(pr.simulations(), 68);
}
