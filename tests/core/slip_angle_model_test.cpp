// The slip-angle model (Ishigami et al. 2007, J. Field Robotics 24(3), with
// Hegedus's sidewall term): reduction to Wong-Reece at beta = 0, values from
// an independent Python calculation, and the trends of the paper's figures.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "core/terramechanics/model.h"
#include "core/terramechanics/slip_angle_model.h"
#include "terramechanics_soils.h"

using namespace roverlab::terramechanics;
using roverlab::test::ding_tyii;
using roverlab::test::dry_sand;
using roverlab::test::kapvik_wheel;

namespace {

constexpr double kDeg = M_PI / 180.0;

ModelOptions riemann(int points) {
  ModelOptions o;
  o.kind = ModelKind::ishigami;
  o.integration = Integration::riemann;
  o.riemann_points = points;
  return o;
}

}  // namespace

TEST(SlipAngleModel, AtZeroSlipAngleItIsTheWongReeceModel) {
  std::vector<Extensions> variants(6);
  variants[1].slip_sinkage_n1 = 0.4;
  variants[4].shear_modulus_slip = 2.0;  // issue 33 item 4's extensions
  variants[4].rear_angle_ratio = 0.3;
  variants[5].shear_peak = true;  // Wong's peaked shear curve, with K_w scaled by slip
  variants[5].shear_residual_ratio = 0.5;
  variants[5].shear_peak_displacement = 0.006;
  variants[5].shear_modulus_slip = 1.0;
  variants[2].grousers = true;
  variants[2].grouser_effectiveness = 0.7;
  variants[3].bulldozing = true;
  variants[3].bulldozing_scale = 2.0;
  variants[3].soil_strength = 0.8;
  Wheel wheel = kapvik_wheel();
  wheel.grouser_count = 24;
  wheel.grouser_height = 0.005;
  int compared = 0, unsupported = 0;
  for (const Extensions& e : variants) {
    for (Integration integration : {Integration::simpson, Integration::riemann}) {
      for (LateralShear shear : {LateralShear::shared, LateralShear::independent}) {
        for (double load : {5.0, 50.0, 150.0}) {
          for (double slip : {-0.6, -0.1, 0.0, 0.2, 0.7, 1.0}) {
            ModelOptions o;
            o.integration = integration;
            o.riemann_points = 300;
            o.extensions = e;
            const Traction w = evaluate(ding_tyii(), wheel, load, slip, o);
            o.kind = ModelKind::ishigami;
            const SlipAngleTraction t = evaluate_slip_angle(ding_tyii(), wheel, load, slip, 0.0, o, {shear, 1.0});
            ++compared;
            EXPECT_EQ(t.status, w.status);  // both carry the load or neither (a weakened soil at 150 N may not)
            if (!w.ok() || !t.ok()) {
              ++unsupported;
              continue;
            }
            EXPECT_NEAR(t.drawbar_pull, w.drawbar_pull, 1e-7 * (1.0 + std::abs(w.drawbar_pull)));
            EXPECT_NEAR(t.resistive_torque, w.resistive_torque, 1e-8 * (1.0 + std::abs(w.resistive_torque)));
            EXPECT_NEAR(t.sinkage, w.sinkage, 1e-10);
            EXPECT_NEAR(t.entry_angle, w.entry_angle, 1e-9);
            EXPECT_NEAR(t.max_stress_angle, w.max_stress_angle, 1e-9);
            EXPECT_EQ(t.lateral_force, 0.0);
          }
        }
      }
    }
  }
  EXPECT_LT(unsupported * 10, compared) << unsupported << " of " << compared << " unsupported";
  // evaluate() with the kind ishigami gives the same (beta = 0) values.
  ModelOptions o;
  o.kind = ModelKind::ishigami;
  EXPECT_EQ(evaluate(ding_tyii(), kapvik_wheel(), 50.0, 0.3, o).drawbar_pull,
            evaluate(ding_tyii(), kapvik_wheel(), 50.0, 0.3).drawbar_pull);
  EXPECT_EQ(parse_model_kind("ishigami"), ModelKind::ishigami);
}

// Rows printed by tests/data/slip_angle/ishigami_reference.py (plain Python,
// written from the paper's equations, not from this C++; rerun it with
// `python3 tests/data/slip_angle/ishigami_reference.py`): ding_tyii, Kapvik
// wheel, midpoint rule with 400 points, entry angle by bisection.
TEST(SlipAngleModel, MatchesTheIndependentPythonCalculation) {
  struct Row {
    bool shared;
    double k_y, load, slip, beta_deg, sinkage, drawbar, torque, lateral, sidewall;
  };
  const Row rows[] = {
      // shared, k_y, load, slip, beta_deg: sinkage_m, DP_N, torque_Nm, Fy_N, sidewall_N
      {true, 0.0114, 50, 0.2, 0, 0.0153479444, 1.5019527, 1.13891537, 0, 0},
      {true, 0.0114, 50, 0.2, 10, 0.0153693744, 0.940084484, 1.09872754, -8.1885898, -0.921233743},
      {true, 0.0114, 50, 0.2, 30, 0.0154929549, -2.14823099, 0.878166187, -19.8162278, -0.935409003},
      {true, 0.0114, 100, 0.5, -20, 0.0244763208, 8.32910566, 3.36940159, 16.0992445, 2.2267996},
      {true, 0.0114, 30, 0.0, 60, 0.011123891, -5.98798485, 0.0631884794, -18.9970569, -0.498727457},
      {true, 0.0200, 50, 0.2, 0, 0.0153479444, 1.5019527, 1.13891537, 0, 0},
      {true, 0.0200, 50, 0.2, 10, 0.0153552779, 1.30861665, 1.12508459, -5.16492247, -0.919623429},
      {true, 0.0200, 50, 0.2, 30, 0.0154117968, -0.147003819, 1.02102867, -13.4990342, -0.926088054},
      {true, 0.0200, 100, 0.5, -20, 0.0244368416, 9.17898402, 3.42728441, 10.2667051, 2.22009125},
      {true, 0.0200, 30, 0.0, 60, 0.0111022889, -5.5339076, 0.0960811054, -16.8961414, -0.496903157},
      {false, 0.0114, 50, 0.2, 0, 0.0153479444, 1.5019527, 1.13891537, 0, 0},
      {false, 0.0114, 50, 0.2, 10, 0.0153479444, 1.5019527, 1.13891537, -9.86446051, -0.918786224},
      {false, 0.0114, 50, 0.2, 30, 0.0153479444, 1.5019527, 1.13891537, -21.0518661, -0.918786224},
      {false, 0.0114, 100, 0.5, -20, 0.0244170624, 9.60680107, 3.45643282, 26.0892536, 2.21673342},
      {false, 0.0114, 30, 0.0, 60, 0.0110383806, -3.96238961, 0.210198057, -18.7736099, -0.491525609},
      {false, 0.0200, 50, 0.2, 0, 0.0153479444, 1.5019527, 1.13891537, 0, 0},
      {false, 0.0200, 50, 0.2, 10, 0.0153479444, 1.5019527, 1.13891537, -6.44217856, -0.918786224},
      {false, 0.0200, 50, 0.2, 30, 0.0153479444, 1.5019527, 1.13891537, -15.2606949, -0.918786224},
      {false, 0.0200, 100, 0.5, -20, 0.0244170624, 9.60680107, 3.45643282, 17.5720462, 2.21673342},
      {false, 0.0200, 30, 0.0, 60, 0.0110383806, -3.96238961, 0.210198057, -16.7614462, -0.491525609},
  };
  for (const Row& row : rows) {
    Soil soil = ding_tyii();
    soil.lateral_shear_modulus = row.k_y;
    const LateralOptions lateral{row.shared ? LateralShear::shared : LateralShear::independent, 1.0};
    const SlipAngleTraction t =
        evaluate_slip_angle(soil, kapvik_wheel(), row.load, row.slip, row.beta_deg * kDeg, riemann(400), lateral);
    SCOPED_TRACE(::testing::Message() << "shared " << row.shared << " k_y " << row.k_y << " W " << row.load << " s "
                                      << row.slip << " beta " << row.beta_deg);
    ASSERT_TRUE(t.ok());
    EXPECT_NEAR(t.sinkage, row.sinkage, 1e-9);
    EXPECT_NEAR(t.drawbar_pull, row.drawbar, 1e-6);
    EXPECT_NEAR(t.resistive_torque, row.torque, 1e-7);
    EXPECT_NEAR(t.lateral_force, row.lateral, 1e-6);
    EXPECT_NEAR(t.sidewall, row.sidewall, 1e-7);
  }
}

TEST(SlipAngleModel, HegedusSidewallResistanceByHand) {
  // phi = 30 deg, c = 0: X_c = 30 deg, D_1 = cot 30 + tan 60 = 2 sqrt(3),
  // D_2 = cot 30 + cot^2 30 tan 30 = 2 sqrt(3), so R_b = 6 gamma h^2.
  Soil soil = dry_sand();
  soil.cohesion = 0.0;
  soil.friction_angle = 30.0 * kDeg;
  soil.density = 1500.0;
  const double gamma = 1500.0 * 9.80665, h = 0.02;
  EXPECT_NEAR(sidewall_resistance(soil, 1.0, h), 6.0 * gamma * h * h, 1e-9);
  // Cohesion adds D_1 c h.
  soil.cohesion = 800.0;
  EXPECT_NEAR(sidewall_resistance(soil, 1.0, h), 6.0 * gamma * h * h + 2.0 * std::sqrt(3.0) * 800.0 * h, 1e-9);
  EXPECT_EQ(sidewall_resistance(soil, 1.0, 0.0), 0.0);
}

TEST(SlipAngleModel, LateralForceOpposesTheSlipAngleRisesAndSaturates) {
  const ModelOptions o = riemann(200);
  for (LateralShear shear : {LateralShear::shared, LateralShear::independent}) {
    std::vector<double> fy;
    for (int deg = 0; deg <= 80; deg += 5) {
      const auto t = evaluate_slip_angle(ding_tyii(), kapvik_wheel(), 60.0, 0.2, deg * kDeg, o, {shear, 1.0});
      ASSERT_TRUE(t.ok());
      fy.push_back(t.lateral_force);
      const auto mirrored = evaluate_slip_angle(ding_tyii(), kapvik_wheel(), 60.0, 0.2, -deg * kDeg, o, {shear, 1.0});
      EXPECT_NEAR(mirrored.lateral_force, -t.lateral_force, 1e-9);  // odd in beta
      EXPECT_NEAR(mirrored.drawbar_pull, t.drawbar_pull, 1e-9);     // even in beta
    }
    EXPECT_EQ(fy[0], 0.0);
    for (std::size_t k = 1; k < fy.size(); ++k) {
      EXPECT_LT(fy[k], 0.0);        // the soil pushes back against +y motion
      EXPECT_LT(fy[k], fy[k - 1]);  // |F_y| rises with beta
    }
    // Saturation (the paper's side-force curves): the rise from 40 to 80 deg is
    // less than half the rise from 0 to 40 deg (measured: 0.39 shared, 0.26
    // independent, ding_tyii at 60 N and s = 0.2), and 80 to 90 deg adds < 3 %.
    EXPECT_LT(std::abs(fy[16] - fy[8]), 0.5 * std::abs(fy[8] - fy[0]));
    const auto sideways = evaluate_slip_angle(ding_tyii(), kapvik_wheel(), 60.0, 0.2, M_PI / 2, o, {shear, 1.0});
    EXPECT_LT(std::abs(sideways.lateral_force - fy[16]), 0.03 * std::abs(fy[16]));
  }
}

TEST(SlipAngleModel, SidewallShareFallsAsTheShearGrows) {
  const ModelOptions o = riemann(200);
  double previous_share = 1.0;
  for (double deg : {2.0, 5.0, 10.0, 20.0, 40.0}) {
    const auto t = evaluate_slip_angle(ding_tyii(), kapvik_wheel(), 60.0, 0.2, deg * kDeg, o);
    ASSERT_TRUE(t.ok());
    EXPECT_NEAR(t.lateral_force, t.lateral_shear + t.sidewall, 1e-12);
    const double share = t.sidewall / t.lateral_force;
    EXPECT_GT(share, 0.0);
    EXPECT_LT(share, previous_share);
    previous_share = share;
  }
  // The sidewall term grows with sinkage (load): about h^2 for cohesionless soil.
  const auto light = evaluate_slip_angle(ding_tyii(), kapvik_wheel(), 20.0, 0.2, 20 * kDeg, o);
  const auto heavy = evaluate_slip_angle(ding_tyii(), kapvik_wheel(), 150.0, 0.2, 20 * kDeg, o);
  EXPECT_GT(std::abs(heavy.sidewall), 3.0 * std::abs(light.sidewall));
  // Switched off, F_y is the shear part alone.
  const auto off =
      evaluate_slip_angle(ding_tyii(), kapvik_wheel(), 60.0, 0.2, 20 * kDeg, o, {LateralShear::shared, 0.0});
  EXPECT_EQ(off.sidewall, 0.0);
  EXPECT_EQ(off.lateral_force, off.lateral_shear);
}

TEST(SlipAngleModel, DrawbarPullFallsWithSlipAngleWhenTheStrengthIsShared) {
  const ModelOptions o = riemann(200);
  for (double slip : {0.1, 0.3, 0.6}) {
    double previous = evaluate_slip_angle(ding_tyii(), kapvik_wheel(), 60.0, slip, 0.0, o).drawbar_pull;
    double first = previous;
    for (int deg = 5; deg <= 60; deg += 5) {
      const auto t = evaluate_slip_angle(ding_tyii(), kapvik_wheel(), 60.0, slip, deg * kDeg, o);
      ASSERT_TRUE(t.ok());
      EXPECT_LT(t.drawbar_pull, previous);
      previous = t.drawbar_pull;
    }
    EXPECT_LT(previous, first - 2.0);  // a drop of several newtons by 60 deg
    // As printed (independent shear), DP does not depend on beta at a given slip.
    const auto printed =
        evaluate_slip_angle(ding_tyii(), kapvik_wheel(), 60.0, slip, 60 * kDeg, o, {LateralShear::independent, 1.0});
    EXPECT_NEAR(printed.drawbar_pull, first, 1e-9);
  }
}

TEST(SlipAngleModel, RefusesBadInput) {
  const double bad[] = {NAN, INFINITY, 91.0 * kDeg, -1.7};
  for (double beta : bad) {
    EXPECT_EQ(evaluate_slip_angle(ding_tyii(), kapvik_wheel(), 50.0, 0.2, beta).status, TractionStatus::invalid_input);
  }
  ModelOptions bekker;
  bekker.kind = ModelKind::bekker;
  EXPECT_EQ(evaluate_slip_angle(ding_tyii(), kapvik_wheel(), 50.0, 0.2, 0.1, bekker).status,
            TractionStatus::invalid_input);
  EXPECT_EQ(evaluate_slip_angle(ding_tyii(), kapvik_wheel(), 1e7, 0.2, 0.1).status, TractionStatus::unsupported_load);
  // 90 deg (sideways) is allowed and finite.
  const auto side = evaluate_slip_angle(ding_tyii(), kapvik_wheel(), 50.0, 1.0, M_PI / 2);
  ASSERT_TRUE(side.ok());
  EXPECT_TRUE(std::isfinite(side.lateral_force));
}

// A travel slip s = 1 - |v| / (r w) (a testbed carriage's speed) is the
// longitudinal slip 1 - (1 - s) cos(beta) with the same beta: by hand,
// s = 0.2 at 30 deg is s_x = 1 - 0.8 x 0.8660254 = 0.30717968. At 90 deg
// the travel reading keeps v_y = (1 - s) r w: its lateral force is the limit
// of longitudinal readings approaching 90 deg with (1 - s_x) tan(beta) fixed.
TEST(SlipAngleModel, ATravelSlipIsTheLongitudinalSlipOfItsVelocity) {
  ModelOptions longitudinal = riemann(200), travel = riemann(200);
  travel.slip_definition = SlipDefinition::travel;
  const auto at = [&](double slip, double deg, const ModelOptions& o) {
    return evaluate_slip_angle(ding_tyii(), kapvik_wheel(), 60.0, slip, deg * kDeg, o);
  };
  for (double slip : {0.0, 0.2, 0.5}) {
    const auto a = at(slip, 0.0, travel), b = at(slip, 0.0, longitudinal);
    EXPECT_EQ(a.drawbar_pull, b.drawbar_pull);  // beta = 0: the same reading
    EXPECT_EQ(a.sinkage, b.sinkage);
  }
  const auto t = at(0.2, 30.0, travel), l = at(0.30717968, 30.0, longitudinal);
  ASSERT_TRUE(t.ok() && l.ok());
  EXPECT_NEAR(t.drawbar_pull, l.drawbar_pull, 1e-6);
  EXPECT_NEAR(t.lateral_force, l.lateral_force, 1e-6);
  EXPECT_NEAR(t.resistive_torque, l.resistive_torque, 1e-7);
  EXPECT_NEAR(t.sinkage, l.sinkage, 1e-9);
  EXPECT_GT(std::abs(t.lateral_force - at(0.2, 30.0, longitudinal).lateral_force), 1.0);  // the readings differ
  // Skidding too: s = -0.5 at 30 deg is s_x = 1 - 1.5 x 0.8660254 = -0.29903811.
  const auto skid = at(-0.5, 30.0, travel), skid_x = at(-0.29903811, 30.0, longitudinal);
  ASSERT_TRUE(skid.ok() && skid_x.ok());
  EXPECT_NEAR(skid.drawbar_pull, skid_x.drawbar_pull, 1e-6);
  EXPECT_NEAR(skid.lateral_force, skid_x.lateral_force, 1e-6);
  EXPECT_NEAR(skid.resistive_torque, skid_x.resistive_torque, 1e-7);
  // Sideways at 90 deg: the travel reading's v_y / (r w) = 0.7 is the
  // longitudinal reading's (1 - s_x) tan(beta) at 89.99 deg.
  const auto side = at(0.3, 90.0, travel);
  const double beta = 89.99;
  const auto limit = at(1.0 - 0.7 / std::tan(beta * kDeg), beta, longitudinal);
  ASSERT_TRUE(side.ok() && limit.ok());
  EXPECT_NEAR(side.lateral_force, limit.lateral_force, 1e-3 * std::abs(limit.lateral_force));
  EXPECT_LT(side.lateral_force, -1.0);
}

// A hint (the entry angles of a previous evaluation) changes where the
// sinkage solve starts, not what it finds: from the point's own last
// solution, from another load's and from nonsense, skidding, driving and
// sideways, the values are the cold start's within the solve's tolerance.
TEST(SlipAngleModel, AHintChangesWhereTheSolveStartsNotWhatItFinds) {
  ModelOptions o;
  o.kind = ModelKind::ishigami;
  o.slip_definition = SlipDefinition::travel;
  for (const double deg : {0.0, 30.0, 90.0}) {
    for (const double slip : {-0.6, 0.0, 0.4, 0.9}) {
      const auto cold = evaluate_slip_angle(dry_sand(), kapvik_wheel(), 40.0, slip, deg * kDeg, o);
      ASSERT_TRUE(cold.ok());
      EntryAngleHint own, other, nonsense{1e-9, 1e-9};
      evaluate_slip_angle(dry_sand(), kapvik_wheel(), 40.0 * (1.0 + 1e-6), slip, deg * kDeg, o, {}, &own);
      evaluate_slip_angle(dry_sand(), kapvik_wheel(), 90.0, slip, deg * kDeg, o, {}, &other);
      EXPECT_GT(own.entry, 0.0);  // the hint was written
      for (EntryAngleHint* h : {&own, &other, &nonsense}) {
        const auto warm = evaluate_slip_angle(dry_sand(), kapvik_wheel(), 40.0, slip, deg * kDeg, o, {}, h);
        ASSERT_TRUE(warm.ok());
        EXPECT_NEAR(warm.sinkage, cold.sinkage, 1e-12 * cold.sinkage) << slip << " at " << deg << " deg";
        EXPECT_NEAR(warm.drawbar_pull, cold.drawbar_pull, 1e-9 * (1.0 + std::abs(cold.drawbar_pull)));
        EXPECT_NEAR(warm.lateral_force, cold.lateral_force, 1e-9 * (1.0 + std::abs(cold.lateral_force)));
        EXPECT_NEAR(warm.resistive_torque, cold.resistive_torque, 1e-9 * (1.0 + std::abs(cold.resistive_torque)));
      }
    }
  }
  // A load the wheel cannot carry is refused with a hint as without.
  EntryAngleHint h{0.3, 0.3};
  EXPECT_EQ(evaluate_slip_angle(dry_sand(), kapvik_wheel(), 1e7, 0.2, 0.0, o, {}, &h).status,
            TractionStatus::unsupported_load);
}
