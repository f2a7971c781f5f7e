// Planar rocker-bogie dynamics (seed 003 chapter 4).
#include <gtest/gtest.h>

#include <cmath>

#include "core/simulation/rocker_bogie.h"
#include "importers/soil_file.h"

using namespace roverlab;

namespace {

simulation::RockerBogieRun flat_run(double seconds) {
  simulation::RockerBogieRun run;
  run.soil = io::load_soil(std::string(ROVERLAB_RESOURCES_DIR) + "/soils/ding_tyii.json");
  run.path = simulation::flat_path();
  run.duration = seconds;
  return run;
}

}  // namespace

TEST(RockerBogie, AtRestTheNormalLoadsCarryTheWeightOfThisSide) {
  const simulation::RockerBogieParameters p;
  const auto r = simulation::simulate_rocker_bogie({}, p, flat_run(0.04));
  const auto& w = r.log.stream("truth/wheels");
  double sum = 0;
  for (int i = 1; i <= 3; ++i) {
    const double W = w.channel("normal_load_" + std::to_string(i)).values.front();
    EXPECT_GT(W, 30.0) << i;
    sum += W;
  }
  const double weight = (p.body_mass + p.bogie_mass + 3 * p.wheel_mass) * p.gravity;
  EXPECT_NEAR(sum, weight, 0.005 * weight);
  // As the geometry says: the bogie pivots midway between wheels 2 and 3, so
  // they carry equal loads; moments about the body's centre of mass (the
  // rocker pivot): wheel 1 is 0.35 m ahead, wheel 3 0.35 m behind, wheel 2
  // under it, the bogie's weight 0.175 m behind.
  const double w1 = w.channel("normal_load_1").values.front(), w2 = w.channel("normal_load_2").values.front(),
               w3 = w.channel("normal_load_3").values.front();
  EXPECT_NEAR(w2, w3, 1e-6 * weight);
  const double mg = p.wheel_mass * p.gravity;
  EXPECT_NEAR(0.35 * (w1 - mg) - 0.35 * (w3 - mg) + 0.175 * p.bogie_mass * p.gravity, 0.0, 1e-3);
}

TEST(RockerBogie, DrivesForwardOnFlatGroundWithTheConstraintsHeld) {
  const auto r = simulation::simulate_rocker_bogie({}, {}, flat_run(60.0));
  EXPECT_LT(r.max_constraint_error, 1e-6);
  const auto& pose = r.log.stream("truth/pose");
  const auto& w = r.log.stream("truth/wheels");
  const double dx = pose.channel("x").values.back() - pose.channel("x").values.front();
  EXPECT_GT(dx, 0.5);  // about 1.5 cm/s after the wheels spin up
  for (int i = 1; i <= 3; ++i) {
    const double s = w.channel("slip_" + std::to_string(i)).values.back();
    EXPECT_GT(s, 0.0) << i;  // driven wheels on soft soil slip
    EXPECT_LT(s, 0.5) << i;
  }
  EXPECT_NEAR(pose.channel("pitch").values.back(), 0.0, 1e-6);
}
