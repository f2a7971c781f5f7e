// Error-state INS with pseudo-measurements (seed 002) on simulated skid-steer
// logs with known biases and slip episodes.
#include <gtest/gtest.h>

#include <cmath>

#include "core/estimation/ins_slip.h"
#include "core/estimation/slip.h"
#include "core/simulation/skid_steer_scenario.h"

using namespace roverlab;
using namespace roverlab::estimation;

TEST(Slip, RatioOfEquation1AndClasses) {
  EXPECT_DOUBLE_EQ(slip_ratio(0.5, 1.0), 0.5);     // wheels faster: slip
  EXPECT_DOUBLE_EQ(slip_ratio(1.0, 0.5), -0.5);    // wheels slower: skid
  EXPECT_DOUBLE_EQ(slip_ratio(0.0, 0.0), 0.0);
  EXPECT_DOUBLE_EQ(slip_ratio(0.7, 0.7), 0.0);
  EXPECT_DOUBLE_EQ(slip_ratio(0.0, 0.3), 1.0);     // spinning in place
  EXPECT_EQ(classify_slip(0.01), SlipClass::none);
  EXPECT_EQ(classify_slip(-0.15), SlipClass::low);
  EXPECT_EQ(classify_slip(0.2), SlipClass::low);
  EXPECT_EQ(classify_slip(0.35), SlipClass::medium);
  EXPECT_EQ(classify_slip(0.7), SlipClass::high);
  EXPECT_EQ(classify_slip(0.71), SlipClass::extreme);
  ConfusionMatrix m;
  m.add(SlipClass::low, SlipClass::low);
  m.add(SlipClass::none, SlipClass::low);
  m.add(SlipClass::none, SlipClass::none);
  EXPECT_DOUBLE_EQ(m.fraction(1, 1), 0.5);  // column-normalised
  EXPECT_DOUBLE_EQ(m.accuracy(), 2.0 / 3.0);
}

namespace {
double truth_of(const log::Log& lg, const std::string& key) { return std::stod(lg.metadata.extra.at(key)); }
}  // namespace

TEST(InsSlip, PseudoMeasurementsBoundTheDriftOfTheInertialSolution) {
  const log::Log lg = simulation::simulate_skid_steer(simulation::default_slip_scenario(1));
  InsSlipOptions pure;
  pure.zupt = pure.zaru = pure.nhc = false;
  const InsSlipResult a = run_ins_slip(lg, pure);
  const InsSlipResult b = run_ins_slip(lg, InsSlipOptions{});
  EXPECT_GT(b.metrics.distance, 50.0);
  EXPECT_GT(a.metrics.final_position_error, 100.0);  // 140 s of free inertial drift
  EXPECT_LT(b.metrics.final_position_error, 0.5);    // with ZUPT, ZARU and NHC
  EXPECT_LT(b.metrics.final_position_error, b.odometry.final_position_error);  // slip fools the wheels
}

TEST(InsSlip, ZuptBoundsVelocityAtStandstill) {
  const log::Log lg = simulation::simulate_skid_steer(simulation::default_slip_scenario(2));
  InsSlipOptions with, without;
  without.zupt = false;
  auto standstill_speed = [&](const InsSlipOptions& o) {
    const InsSlipResult r = run_ins_slip(lg, o);
    const auto& v = r.estimates.stream("estimate/ins/velocity");
    const auto& still = r.estimates.stream("estimate/ins/standstill").channel("standstill").values;
    double worst = 0.0;
    for (std::size_t i = 0; i < still.size(); ++i) {
      if (still[i] > 0.5 && v.time()[i] > 10.0) {
        worst = std::max(worst, std::hypot(v.channel("north").values[i], v.channel("east").values[i]));
      }
    }
    return worst;
  };
  EXPECT_LT(standstill_speed(with), 0.05);
  EXPECT_GT(standstill_speed(without), 0.1);
}

TEST(InsSlip, ZaruEstimatesTheInjectedGyroBias) {
  const log::Log lg = simulation::simulate_skid_steer(simulation::default_slip_scenario(3));
  const InsSlipResult r = run_ins_slip(lg, InsSlipOptions{});
  const auto& b = r.estimates.stream("estimate/ins/bias");
  for (const char* axis : {"x", "y", "z"}) {
    const double truth = truth_of(lg, std::string("truth/gyro_bias_") + axis);
    EXPECT_NEAR(b.channel(std::string("gyro_") + axis).values.back(), truth, 3e-5) << axis;
  }
  InsSlipOptions no_zaru;
  no_zaru.zaru = false;
  const InsSlipResult r2 = run_ins_slip(lg, no_zaru);
  const auto& b2 = r2.estimates.stream("estimate/ins/bias");
  EXPECT_GT(std::abs(b2.channel("gyro_z").values.back() - truth_of(lg, "truth/gyro_bias_z")), 5e-5);
}

TEST(InsSlip, SlipClassesOnASimulatedDriveWithKnownEpisodes) {
  const log::Log lg = simulation::simulate_skid_steer(simulation::default_slip_scenario(1));
  const InsSlipResult r = run_ins_slip(lg, InsSlipOptions{});
  const ConfusionMatrix& c = r.metrics.confusion;
  ASSERT_GT(c.truth_total(0), 100);
  ASSERT_GT(c.truth_total(1), 500);
  EXPECT_GE(c.fraction(0, 0), 0.995);  // no slip (standstill)
  EXPECT_GE(c.fraction(1, 1), 0.94);   // low slip (6 % nominal, 8-15 % episodes)
  for (int k = 2; k < kSlipClasses; ++k) EXPECT_GE(c.fraction(k, k), 0.95) << to_string(static_cast<SlipClass>(k));
}
