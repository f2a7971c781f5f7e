// Issue 33 item 5: the contact-angle scenarios' steering manoeuvre and its
// hidden slip angle (FlyingRoverScenario::turn_radius, slip_angle) — the
// truth the scenario writes, and model selection finding the effect.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "core/common/error.h"
#include "core/estimation/contact_angle/contact_angle.h"
#include "core/estimation/contact_angle/model_selection.h"
#include "core/simulation/flying_rover.h"
#include "importers/rover_file.h"

using namespace roverlab;

namespace {

const kinematics::RoverModel& bb2() {
  static const kinematics::RoverModel m =
      *io::load_rover(std::string(ROVERLAB_RESOURCES_DIR) + "/rovers/exomars_bb2.json").dh;
  return m;
}

const char* const kWheels[6] = {"FL", "ML", "RL", "RR", "MR", "FR"};

// The BB2's wheel centres in the body frame at zero joint angles, by hand
// from seed 000 Table 4.2 (as in contact_angle_test.cpp): x, y in metres.
const double kCentre[6][2] = {{0.6505, 0.5933},  {0.0105, 0.6013},  {-0.698, 0.6043},
                              {-0.698, -0.5963}, {0.0105, -0.5933}, {0.6505, -0.6013}};

simulation::FlyingRoverScenario manoeuvre(const std::string& name, double turn_radius, double slip_angle_deg,
                                          unsigned seed = 1) {
  auto s = simulation::flying_rover_scenario(name, bb2());
  s.turn_radius = turn_radius;
  s.slip_angle = slip_angle_deg * M_PI / 180.0;
  s.seed = seed;
  return s;
}

}  // namespace

// The truth against planar rigid-body kinematics, computed apart from the
// simulator's DH chain: a wheel at (x, y) on a body moving at V along x and
// turning at r = V / R travels along atan2(r x, V - r y); its heading is its
// steering angle (vertical steering axes, positive to the left), read from
// the joints stream; its slip angle is the travel's angle left of the heading
// (seed 000 section 5.2, beta = atan(v.y_c / v.x_c)), and it must be the
// injected one.
TEST(SlipAngleScenario, TruthSideSlipIsTheInjectedSlipAngleByPlanarKinematics) {
  struct Case {
    double radius, beta_deg;
  };
  for (const Case c : {Case{1.5, 7.0}, Case{-1.0, -12.0}, Case{INFINITY, 10.0}}) {
    auto s = manoeuvre("flat-turn", c.radius, c.beta_deg);
    s.noise = false;
    s.rate = 20.0;
    const log::Log lg = simulation::simulate_flying_rover(bb2(), s);
    const auto& truth = lg.stream("truth/wheels");
    const auto& joints = lg.stream("joints");
    const auto& imu = lg.stream("imu");
    const double V = s.speed, r = std::isfinite(c.radius) ? V / c.radius : 0.0;
    const std::size_t i = truth.size() / 2;
    for (int w = 0; w < 6; ++w) {
      const std::string n = kWheels[w];
      const double travel = std::atan2(r * kCentre[w][0], V - r * kCentre[w][1]);
      const double heading = joints.channel("steer_" + n).values[i];
      const double side_slip = truth.channel("side_slip_" + n).values[i];
      EXPECT_NEAR(side_slip, travel - heading, 1e-9) << n << " R " << c.radius;
      EXPECT_NEAR(side_slip, c.beta_deg * M_PI / 180.0, 1e-9) << n << " R " << c.radius;
      EXPECT_NEAR(truth.channel("contact_angle_" + n).values[i], 0.0, 1e-12) << n;
      // Each wheel rolls without slip along its plane: rate r_w = |v| cos(beta).
      EXPECT_NEAR(truth.channel("slip_" + n).values[i], 0.0, 1e-9) << n;
      const double speed = std::hypot(V - r * kCentre[w][1], r * kCentre[w][0]);
      EXPECT_NEAR(lg.stream("wheels").channel("rate_" + n).values[i] * bb2().wheel_radius,
                  speed * std::cos(c.beta_deg * M_PI / 180.0), 1e-9)
          << n;
    }
    // The IMU of a level body in a steady turn: yaw rate r, centripetal force r V to the left.
    EXPECT_NEAR(imu.channel("angular_rate_z").values[i], r, 1e-12);
    EXPECT_NEAR(imu.channel("specific_force_y").values[i], r * V, 1e-12);
    EXPECT_NEAR(lg.stream("truth/body").channel("yaw").values[i],
                std::remainder(r * lg.stream("truth/body").time()[i], 2 * M_PI), 1e-12);
  }
}

TEST(SlipAngleScenario, ARampedSlipAngleTurnsTheSteeringAtItsMeasuredRateAndTheTruthFollows) {
  auto s = manoeuvre("flat-turn", 1.0, -8.0);
  s.slip_angle_from = 10.0;
  s.noise = false;
  s.rate = 100.0;
  const log::Log lg = simulation::simulate_flying_rover(bb2(), s);
  const auto& truth = lg.stream("truth/wheels");
  const auto& joints = lg.stream("joints");
  const auto& t = truth.time();
  const double beta = -8.0 * M_PI / 180.0;
  for (std::size_t i = 1; i + 1 < t.size(); ++i) {
    const double share = std::clamp((t[i] - 10.0) / simulation::FlyingRoverScenario::kSlipAngleRamp, 0.0, 1.0);
    for (int w = 0; w < 6; ++w) {
      const std::string n = kWheels[w];
      ASSERT_NEAR(truth.channel("side_slip_" + n).values[i], share * beta, 1e-9) << n << " t " << t[i];
      ASSERT_NEAR(truth.channel("slip_" + n).values[i], 0.0, 1e-9) << n << " t " << t[i];
    }
    // The steering rate the log reports is the angle's derivative (central difference off the ramp's corners).
    if (std::abs(t[i] - 10.0) > 0.015 && std::abs(t[i] - 11.0) > 0.015) {
      const auto& a = joints.channel("steer_FL").values;
      EXPECT_NEAR(joints.channel("steer_FL_rate").values[i], (a[i + 1] - a[i - 1]) / (t[i + 1] - t[i - 1]), 1e-9)
          << t[i];
    }
  }
  auto bad = s;
  bad.slip_angle_from = 30.0;  // the run's end
  EXPECT_THROW(simulation::simulate_flying_rover(bb2(), bad), DataError);
}

TEST(SlipAngleScenario, WithoutTheManoeuvreTheScenariosAreUnchangedAndBadValuesAreRefused) {
  // A scenario's own steering is kept and offset: bump-crossing's steering plus -beta on a straight run.
  auto plain = simulation::flying_rover_scenario("bump-crossing", bb2());
  plain.noise = false;
  plain.rate = 20.0;
  auto crab = plain;
  crab.slip_angle = 0.1;
  const log::Log a = simulation::simulate_flying_rover(bb2(), plain),
                 b = simulation::simulate_flying_rover(bb2(), crab);
  const std::size_t i = 123;
  EXPECT_NEAR(b.stream("joints").channel("steer_ML").values[i], a.stream("joints").channel("steer_ML").values[i] - 0.1,
              1e-9);
  EXPECT_EQ(a.stream("wheels").channel("rate_FL").values[i], plain.speed / bb2().wheel_radius);
  EXPECT_EQ(a.stream("imu").channel("angular_rate_z").values[i], 0.0);
  auto bad = plain;
  bad.turn_radius = 0.5;  // the turn's centre between the wheels
  EXPECT_THROW(simulation::simulate_flying_rover(bb2(), bad), DataError);
  bad = plain;
  bad.slip_angle = 1.0;
  EXPECT_THROW(simulation::simulate_flying_rover(bb2(), bad), DataError);
}

namespace {

estimation::ModelSelection select_on(const simulation::FlyingRoverScenario& s) {
  const log::Log lg = simulation::simulate_flying_rover(bb2(), s);
  estimation::ContactAngleOptions o;
  o.reset_cross_covariance = true;  // the command line's default
  return estimation::select_contact_model(lg, bb2(), o, {});
}

}  // namespace

// Model selection at the command line's defaults (1 kHz, the reset) finds
// the hidden slip angle in a 1 m turn on three noise seeds and does not claim
// it on the same turn without one; the side-slip estimate then errs by less
// than the effect it finds (docs/validation/contact-angle.md, "A hidden slip
// angle").
TEST(SlipAngleScenario, ModelSelectionFindsTheSlipAngleInATurnAndNotWithoutIt) {
  const auto none = select_on(manoeuvre("flat-turn", 1.0, 0.0, 1));
  EXPECT_NE(none.chosen, estimation::ContactModel::contact_side_slip) << none.reason;
  for (unsigned seed : {1u, 2u, 3u}) {
    const auto found = select_on(manoeuvre("flat-turn", 1.0, 5.0, seed));
    ASSERT_EQ(found.chosen, estimation::ContactModel::contact_side_slip) << "seed " << seed << ": " << found.reason;
    EXPECT_TRUE(found.supported) << seed;
    double mean = 0;
    for (double e : found.result.rms.side_slip) mean += e / 6.0;
    EXPECT_LT(mean, 5.0 * M_PI / 180.0) << "seed " << seed;
  }
}
