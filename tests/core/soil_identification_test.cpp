#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "core/terramechanics/rft.h"
#include "core/terramechanics/soil_identification.h"
#include "terramechanics_soils.h"

using namespace roverlab::terramechanics;

namespace {

std::vector<WheelTestPoint> synthetic_points(const Soil& soil, const ModelOptions& model, unsigned seed,
                                             const MeasurementSigma& sigma) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> unit(0.0, 1.0);
  std::vector<WheelTestPoint> points;
  for (double load : {60.0, 100.0, 140.0}) {
    for (double slip = 0.0; slip <= 0.71; slip += 0.1) {
      WheelTestPoint p;
      p.wheel = {0.157, 0.165, 0, 0.0};
      p.load = load;
      p.slip = slip;
      const Traction t = evaluate(soil, p.wheel, load, slip, model);
      p.drawbar_pull = t.drawbar_pull + sigma.drawbar_pull * unit(rng);
      p.torque = t.resistive_torque + sigma.torque * unit(rng);
      p.sinkage = t.sinkage + sigma.sinkage * unit(rng);
      points.push_back(p);
    }
  }
  return points;
}

}  // namespace

TEST(SoilIdentification, RecoversSoilParametersWithinTwoSigma) {
  Soil truth = roverlab::test::ding_tyii();
  truth.cohesion = 600.0;
  truth.friction_angle = 0.52;
  truth.shear_modulus = 0.018;
  const MeasurementSigma sigma;
  const auto points = synthetic_points(truth, {}, 11, sigma);

  IdentificationOptions options;
  options.free = {Parameter::cohesion, Parameter::friction_angle, Parameter::shear_modulus};
  const IdentificationResult r = identify_soil(roverlab::test::ding_tyii(), points, options);
  EXPECT_TRUE(r.converged) << r.message;
  ASSERT_TRUE(r.covariance_ok);
  ASSERT_EQ(r.parameters.size(), 3u);
  const double truth_values[3] = {600.0, 0.52, 0.018};
  for (int k = 0; k < 3; ++k) {
    const auto& p = r.parameters[static_cast<std::size_t>(k)];
    EXPECT_GT(p.sigma, 0.0);
    EXPECT_LT(std::abs(p.value - truth_values[k]), 2.0 * p.sigma)
        << to_string(p.parameter) << " = " << p.value << " +- " << p.sigma;
  }
  // Residuals are at the noise level: chi2 per measurement about one.
  EXPECT_EQ(r.measurements, points.size() * 3);
  EXPECT_LT(r.chi2 / static_cast<double>(r.measurements), 1.5);
  EXPECT_EQ(r.residuals.size(), r.measurements);
}

TEST(SoilIdentification, BoundsHoldAndAreReported) {
  Soil truth = roverlab::test::ding_tyii();
  ModelOptions strong;
  strong.extensions.soil_strength = 8.0;  // beyond the bound of 5
  const auto points = synthetic_points(truth, strong, 5, MeasurementSigma{});
  IdentificationOptions options;
  options.free = {Parameter::soil_strength};
  const IdentificationResult r = identify_soil(truth, points, options);
  ASSERT_EQ(r.parameters.size(), 1u);
  EXPECT_LE(r.parameters[0].value, default_bounds(Parameter::soil_strength).upper + 1e-12);
  EXPECT_TRUE(r.parameters[0].at_bound);
}

TEST(SoilIdentification, RobustLossResistsAnOutlier) {
  const Soil truth = roverlab::test::ding_tyii();
  ModelOptions weak;
  weak.extensions.soil_strength = 0.8;
  auto points = synthetic_points(truth, weak, 7, MeasurementSigma{});
  *points[5].drawbar_pull += 40.0;  // a gross error: 80 sigma
  IdentificationOptions robust, plain;
  robust.free = plain.free = {Parameter::soil_strength};
  plain.huber_sigmas = 0.0;
  const double with_huber = identify_soil(truth, points, robust).parameters[0].value;
  const double without = identify_soil(truth, points, plain).parameters[0].value;
  EXPECT_LT(std::abs(with_huber - 0.8), std::abs(without - 0.8));
  EXPECT_NEAR(with_huber, 0.8, 0.01);
}

// A fit by numeric differences (RFT) whose parameter ends at a bound past
// which the model does not exist (a pile-up below 0): its central
// difference there used to fail the evaluation, and Ceres ended the fit
// with the start value (on the Ding rows, a pile-up of 0.3 reported with a
// delta BIC of +18). Now the fit reaches the bound.
TEST(SoilIdentification, ANumericFitReachesABoundWhereTheModelEnds) {
  const Soil soil = roverlab::test::dry_sand();
  ModelOptions model;
  model.kind = ModelKind::rft;
  std::vector<WheelTestPoint> points;
  for (double load : {40.0, 80.0}) {
    for (double angle : {0.0, 0.5, 1.0}) {
      for (double slip : {0.1, 0.4, 0.7}) {
        WheelTestPoint p;
        p.wheel = {0.1, 0.1, 0, 0.0};
        p.load = load;
        p.slip = slip;
        p.slip_angle = angle;
        const SlipAngleTraction t = evaluate_rft(soil, p.wheel, load, slip, angle, model);
        ASSERT_TRUE(t.ok());
        p.drawbar_pull = t.drawbar_pull * (1.0 + 0.01 * std::sin(7.0 * slip + angle));  // a little misfit
        p.sinkage = t.sinkage;
        p.lateral_force = t.lateral_force;
        points.push_back(p);
      }
    }
  }
  IdentificationOptions io;
  io.model = model;
  io.model.extensions.rft_pileup = 0.3;  // the pile-up candidate's start
  io.free = {Parameter::rft_scale, Parameter::rft_pileup};
  const IdentificationResult r = identify_soil(soil, points, io);
  EXPECT_TRUE(r.converged) << r.message;
  ASSERT_EQ(r.parameters.size(), 2u);
  EXPECT_LT(r.parameters[1].value, 1e-3) << r.message;
  EXPECT_TRUE(r.parameters[1].at_bound);
  EXPECT_NEAR(r.parameters[0].value, soil.rft_scale, 0.05 * soil.rft_scale);
}
