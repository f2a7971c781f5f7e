// Planar rocker-bogie dynamics (seed 003 chapter 4).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "core/common/error.h"
#include "core/simulation/rocker_bogie.h"
#include "core/simulation/rocker_bogie_dynamics.h"
#include "core/terramechanics/slip_angle_model.h"
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

namespace {

log::Log run_with(const std::string& effect, double value, double seconds = 12.0) {
  auto run = flat_run(seconds);
  run.seed = 3;
  if (!effect.empty()) simulation::set_effect(run.effects, effect, value);
  return simulation::simulate_rocker_bogie({}, {}, run).log;
}

const std::vector<double>& ch(const log::Log& lg, const char* stream, const std::string& channel) {
  return lg.stream(stream).channel(channel).values;
}

double mean_tail(const std::vector<double>& v, std::size_t n) {
  double s = 0;
  for (std::size_t i = v.size() - n; i < v.size(); ++i) s += v[i];
  return s / static_cast<double>(n);
}

}  // namespace

TEST(RockerBogieEffects, SwitchedOffTheLogIsTheBaselineBitForBit) {
  const log::Log a = run_with("", 0), b = run_with("gyro-bias", 0.0);
  ASSERT_EQ(a.streams().size(), b.streams().size());
  for (std::size_t s = 0; s < a.streams().size(); ++s) {
    const auto& x = a.streams()[s];
    const auto& y = b.streams()[s];
    EXPECT_EQ(x.time(), y.time()) << x.name();
    for (std::size_t c = 0; c < x.channels().size(); ++c)
      EXPECT_EQ(x.channels()[c].values, y.channels()[c].values) << x.name();
  }
  EXPECT_EQ(a.metadata.extra.count("truth/effect/gyro-bias"), 0u);
}

TEST(RockerBogieEffects, SensorEffectsChangeOnlyTheirSensorAsTheyShould) {
  const log::Log base = run_with("", 0);
  const log::Log gyro = run_with("gyro-bias", 0.01), acc = run_with("accel-bias", 0.05),
                 off = run_with("force-offset", 1.5);
  const log::Log scale = run_with("force-scale", 1.1), drop = run_with("encoder-dropout", 5.0),
                 shift = run_with("imu-time-offset", 0.2);
  const auto& r0 = ch(base, "imu", "pitch_rate");
  const auto& r1 = ch(gyro, "imu", "pitch_rate");
  for (std::size_t i = 0; i < r0.size(); ++i) EXPECT_NEAR(r1[i] - r0[i], 0.01, 1e-12);
  EXPECT_EQ(ch(base, "forces", "load_1"), ch(gyro, "forces", "load_1"));  // untouched
  for (const char* c : {"specific_force_x", "specific_force_z"}) {
    EXPECT_NEAR(ch(acc, "imu", c)[100] - ch(base, "imu", c)[100], 0.05, 1e-12);
  }
  EXPECT_NEAR(ch(off, "forces", "perpendicular_2")[300] - ch(base, "forces", "perpendicular_2")[300], 1.5, 1e-12);
  // A scale error grows with the load: 10 % of about 45 N.
  const double dl = ch(scale, "forces", "load_1")[300] - ch(base, "forces", "load_1")[300];
  EXPECT_NEAR(dl, 0.1 * ch(base, "truth/wheels", "normal_load_1")[300], 0.2);
  // Dropout: encoders frozen for 2 s from 5 s, then back.
  const auto& q = ch(drop, "joints", "wheel_angle_1");
  const auto& tq = drop.stream("joints").time();
  const std::size_t a = drop.stream("joints").nearest_index(5.1), b = drop.stream("joints").nearest_index(6.9);
  EXPECT_EQ(q[a], q[b]);
  EXPECT_GT(tq[b] - tq[a], 1.7);
  EXPECT_NE(ch(base, "joints", "wheel_angle_1")[a], ch(base, "joints", "wheel_angle_1")[b]);
  EXPECT_EQ(q.back(), ch(base, "joints", "wheel_angle_1").back());
  // Time offset: the IMU's clock only.
  EXPECT_NEAR(shift.stream("imu").time()[10] - base.stream("imu").time()[10], 0.2, 1e-12);
  EXPECT_EQ(ch(shift, "imu", "pitch_rate"), ch(base, "imu", "pitch_rate"));
  EXPECT_EQ(shift.stream("joints").time(), base.stream("joints").time());
}

TEST(RockerBogieEffects, PhysicalEffectsMoveTheRoverAsTheirPhysicsSays) {
  const log::Log base = run_with("", 0);
  auto distance = [](const log::Log& lg) {
    const auto& x = ch(lg, "truth/pose", "x");
    return x.back() - x.front();
  };
  auto slip = [](const log::Log& lg) { return mean_tail(ch(lg, "truth/wheels", "slip_2"), 100); };
  // Larger wheels than the controller assumes: the same wheel rate covers more ground.
  EXPECT_GT(distance(run_with("wheel-radius-scale", 1.1)), 1.05 * distance(base));
  // A stronger soil and grousers grip better: less slip.
  EXPECT_LT(slip(run_with("soil-strength", 2.0)), slip(base) - 0.02);
  EXPECT_LT(slip(run_with("grousers", 0.01)), slip(base) - 0.02);
  // Slip-sinkage digs the wheels in: deeper, and more slip.
  const log::Log dig = run_with("slip-sinkage", 0.5);
  EXPECT_GT(slip(dig), slip(base) + 0.01);
  EXPECT_GT(mean_tail(ch(dig, "truth/wheels", "sinkage_2"), 100),
            1.1 * mean_tail(ch(base, "truth/wheels", "sinkage_2"), 100));
  // An effect that starts further on leaves the beginning untouched.
  auto run = flat_run(12.0);
  run.seed = 3;
  run.effects.soil_strength = 2.0;
  run.effects.effect_start_x = 1e6;
  EXPECT_EQ(ch(simulation::simulate_rocker_bogie({}, {}, run).log, "truth/wheels", "slip_2"),
            ch(base, "truth/wheels", "slip_2"));
}

TEST(RockerBogie, SteadySlipOnFlatGroundIsWhereTheTerramechanicsBalances) {
  const simulation::RockerBogieParameters p;
  const auto r = simulation::simulate_rocker_bogie({}, p, flat_run(60.0));
  const auto& w = r.log.stream("truth/wheels");
  const auto& cmd = r.log.stream("commands");
  const std::size_t k = w.size() - 1;
  // Constant speed: the drawbar pulls cancel (no net force on the rover) ...
  double dp = 0;
  for (int i = 1; i <= 3; ++i) dp += w.channel("drawbar_pull_" + std::to_string(i)).values[k];
  EXPECT_NEAR(dp, 0.0, 0.3);
  // ... and each motor torque equals the model's resistive torque at that
  // wheel's load and slip plus the drivetrain's viscous loss.
  const auto soil = io::load_soil(std::string(ROVERLAB_RESOURCES_DIR) + "/soils/ding_tyii.json");
  for (int i = 1; i <= 3; ++i) {
    const std::string n = std::to_string(i);
    const double W = w.channel("normal_load_" + n).values[k], s = w.channel("slip_" + n).values[k];
    const auto model = terramechanics::evaluate(soil, {0.075, 0.07, 0, 0.0}, W, s);
    ASSERT_TRUE(model.ok());
    const double torque = cmd.channel("wheel_torque_" + n).values[k];
    const double expected = model.resistive_torque + p.wheel_damping * w.channel("wheel_rate_" + n).values[k];
    EXPECT_NEAR(torque, expected, 0.05 * std::abs(expected) + 0.02) << i;
    EXPECT_NEAR(w.channel("sinkage_" + n).values[k], model.sinkage, 0.1 * model.sinkage) << i;
  }
}

// Issue 33, item 5: wheels at a slip angle (a steering manoeuvre, or crabbing
// across a side slope) lose drawbar pull to the lateral shear (Ishigami 2007
// with one shared Mohr-Coulomb strength): the rover slips more, and each
// motor's steady torque is the slip-angle model's resistive torque at that
// wheel's load and slip, not the straight wheel's.
TEST(RockerBogieEffects, ASlipAngleCostsDrawbarPullAndTheTorqueIsTheSlipAngleModels) {
  const log::Log base = run_with("", 0, 60.0), steered = run_with("slip-angle", 30.0, 60.0);
  EXPECT_GT(mean_tail(ch(steered, "truth/wheels", "slip_2"), 100),
            mean_tail(ch(base, "truth/wheels", "slip_2"), 100) + 0.02);
  const auto soil = io::load_soil(std::string(ROVERLAB_RESOURCES_DIR) + "/soils/ding_tyii.json");
  const simulation::RockerBogieParameters p;
  const auto& w = steered.stream("truth/wheels");
  const std::size_t k = w.size() - 1;
  for (int i = 1; i <= 3; ++i) {
    const std::string n = std::to_string(i);
    const double W = w.channel("normal_load_" + n).values[k], s = w.channel("slip_" + n).values[k];
    const auto at_angle = terramechanics::evaluate_slip_angle(soil, {0.075, 0.07, 0, 0.0}, W, s, 30.0 * M_PI / 180);
    const auto straight = terramechanics::evaluate(soil, {0.075, 0.07, 0, 0.0}, W, s);
    ASSERT_TRUE(at_angle.ok() && straight.ok());
    const double loss = p.wheel_damping * w.channel("wheel_rate_" + n).values[k];
    const double torque = ch(steered, "commands", "wheel_torque_" + n)[k];
    const double tolerance = 0.05 * std::abs(at_angle.resistive_torque + loss) + 0.02;
    EXPECT_NEAR(torque, at_angle.resistive_torque + loss, tolerance) << i;
    EXPECT_GT(std::abs(torque - straight.resistive_torque - loss), tolerance) << i;  // the straight wheel's is not it
  }
}

// The model apart from the simulator (core/simulation/rocker_bogie_dynamics.h).
TEST(RockerBogieDynamics, TheVelocityJacobiansAreTheDerivativesOfThePositions) {
  namespace rb = simulation::rocker_bogie;
  const simulation::PlanarRockerBogieGeometry g;
  const simulation::RockerBogieParameters p;
  rb::Vec q;
  q << 0.3, 0.2, 0.1, -0.2, 1.0, 2.0, 3.0;
  const rb::Kinematics k = rb::kinematics(g, p, q);
  const double h = 1e-6;
  for (int c = 0; c < rb::N; ++c) {
    rb::Vec d = rb::Vec::Zero();
    d(c) = h;
    const rb::Kinematics kp = rb::kinematics(g, p, q + d), km = rb::kinematics(g, p, q - d);
    EXPECT_LT(((kp.bogie_com - km.bogie_com) / (2 * h) - k.J_bogie.col(c)).norm(), 1e-8) << c;
    for (int i = 0; i < 3; ++i)
      EXPECT_LT(((kp.wheel[i] - km.wheel[i]) / (2 * h) - k.J_wheel[i].col(c)).norm(), 1e-8) << c;
  }
}

// The Jacobians' rates in closed form (issue 34, N8: they replaced two of
// the three kinematics per evaluation) are the Jacobians' derivatives along qd.
TEST(RockerBogieDynamics, TheJacobianRatesAreTheDerivativesOfTheJacobians) {
  namespace rb = simulation::rocker_bogie;
  const simulation::PlanarRockerBogieGeometry g;
  const simulation::RockerBogieParameters p;
  rb::Vec q, qd;
  q << 0.3, 0.2, 0.1, -0.2, 1.0, 2.0, 3.0;
  qd << 0.02, -0.01, 0.3, -0.5, 0.2, 0.3, 0.4;
  const double e = 1e-5;
  const rb::Kinematics k = rb::kinematics(g, p, q), kp = rb::kinematics(g, p, q + e * qd),
                       km = rb::kinematics(g, p, q - e * qd);
  const rb::JacobianRates r = rb::jacobian_rates(g, k, q, qd);
  const rb::Jac bogie = (kp.J_bogie - km.J_bogie) / (2 * e);
  EXPECT_GT(bogie.norm(), 1e-3);
  EXPECT_LT((r.bogie - bogie).norm(), 1e-8);
  for (int i = 0; i < 3; ++i) {
    const rb::Jac wheel = (kp.J_wheel[i] - km.J_wheel[i]) / (2 * e);
    EXPECT_GT(wheel.norm(), 1e-3) << i;
    EXPECT_LT((r.wheel[i] - wheel).norm(), 1e-8) << i;
  }
}

// Hdot qd from the Jacobians' rates (issue 34, N8: the two 7x7 inertia
// builds per evaluation were a quarter of the simulation) equals the
// difference of Eq. 4.29's inertia along qd.
TEST(RockerBogieDynamics, TheInertiaRateIsTheDerivativeOfTheInertia) {
  namespace rb = simulation::rocker_bogie;
  const simulation::PlanarRockerBogieGeometry g;
  const simulation::RockerBogieParameters p;
  rb::Vec q, qd;
  q << 0.3, 0.2, 0.1, -0.2, 1.0, 2.0, 3.0;
  qd << 0.02, -0.01, 0.3, -0.5, 0.2, 0.3, 0.4;
  const double e = 1e-4;
  const rb::Vec expected =
      (rb::inertia(rb::kinematics(g, p, q + e * qd), p) - rb::inertia(rb::kinematics(g, p, q - e * qd), p)) / (2 * e) *
      qd;
  const rb::Kinematics k = rb::kinematics(g, p, q);
  const rb::Vec got = rb::inertia_rate_times(k, rb::jacobian_rates(g, k, q, qd), p, qd);
  EXPECT_GT(expected.norm(), 1e-3);
  EXPECT_LT((got - expected).norm(), 1e-6 * expected.norm()) << got.transpose() << "\n" << expected.transpose();
}

TEST(RockerBogieDynamics, APlacedRoverAtRestStaysThereWithTheConstraintsCarryingItsWeight) {
  namespace rb = simulation::rocker_bogie;
  const simulation::PlanarRockerBogieGeometry g;
  const simulation::RockerBogieParameters p;
  const auto run = flat_run(1.0);
  rb::Dynamics dynamics(g, p, run);
  rb::Vec q, qd = rb::Vec::Zero(), qdd;
  q << -0.35, 0.175, 0, 0, 0, 0, 0;  // wheel 1 at x = 0; all three wheel centres on z = 0
  rb::DynamicsReport report;
  dynamics.accelerations(q, qd, qdd, &report);  // no normal load held yet: no traction
  EXPECT_LT(qdd.norm(), 1e-9);
  const double weight = (p.body_mass + p.bogie_mass + 3 * p.wheel_mass) * p.gravity;
  EXPECT_NEAR(report.lambda.sum(), weight, 1e-9 * weight);
  // The Odeint system is [qdd; qd] of the same model.
  rb::State x(2 * rb::N), dx(2 * rb::N);
  for (int i = 0; i < rb::N; ++i) x[static_cast<std::size_t>(rb::N + i)] = q(i);
  rb::OdeSystem{&dynamics}(x, dx, 0.0);
  for (int i = 0; i < rb::N; ++i) EXPECT_EQ(dx[static_cast<std::size_t>(i)], qdd(i));
}

// Issue 34, N10 and item 2: for every soil strength the simulator accepts,
// on flat ground and on the slopes of the bundled scenarios (5 deg, and the
// rolling path's steepest 11 deg) and steeper, a driven rover never moves
// against its driving faster than the 4 mm/s band in which the traction is
// regularised through standstill (before: -96 m/s on flat ground at 0.5;
// -8 m/s on 11 deg at 0.5, -53 m/s on 20 deg, where the compaction
// resistance was pushed downhill with the slide), and its wheels never sink
// as deep as their radius. A soil that cannot carry a wheel's share of the
// rover below its axle is refused (before: 0.137 m of sinkage at 0.1).
TEST(RockerBogie, NoSoilDrivesTheRoverBackwardsOrSinksItsWheels) {
  const double radius = simulation::PlanarRockerBogieGeometry{}.wheel_radius;
  for (double slope : {0.0, 5.0, 11.0, 20.0}) {
    for (double strength : {0.25, 0.3, 0.5, 0.7, 1.0, 2.0, 5.0, 10.0}) {
      auto run = flat_run(15.0);
      run.path = slope == 0.0 ? simulation::flat_path() : simulation::slope_path(slope);
      run.seed = 3;
      simulation::set_effect(run.effects, "soil-strength", strength);
      const log::Log lg = simulation::simulate_rocker_bogie({}, {}, run).log;
      const std::vector<double>& x = ch(lg, "truth/pose", "x");
      const std::vector<double>& t = lg.stream("truth/pose").time();
      double fastest_back = 0.0;
      for (std::size_t k = 1; k < x.size(); ++k)
        fastest_back = std::max(fastest_back, -(x[k] - x[k - 1]) / (t[k] - t[k - 1]));
      EXPECT_LT(fastest_back, 0.004) << "slope " << slope << " deg, soil strength " << strength;
      EXPECT_GT(x.back(), x.front() - (slope == 0.0 ? 0.001 : 0.1)) << "slope " << slope << ", strength " << strength;
      double deepest = 0.0;
      for (int i = 1; i <= 3; ++i) {
        for (double s : ch(lg, "truth/wheels", "sinkage_" + std::to_string(i))) deepest = std::max(deepest, s);
      }
      EXPECT_LT(deepest, radius) << "slope " << slope << " deg, soil strength " << strength;
    }
  }
  // Weaker, the wheel-soil model has no entry angle below 90 deg for the
  // loads: refused, naming the soil.
  for (double strength : {0.1, 0.2}) {
    auto run = flat_run(1.0);
    simulation::set_effect(run.effects, "soil-strength", strength);
    try {
      simulation::simulate_rocker_bogie({}, {}, run);
      ADD_FAILURE() << "soil strength " << strength << " was simulated";
    } catch (const DataError& e) {
      EXPECT_NE(std::string(e.what()).find("sinks past its axle"), std::string::npos) << e.what();
    }
  }
}
