// Wong-Reece and Bekker wheel models against seed 003 (Setterfield 2011),
// chapter 2: Table 2.2, Table 2.3, Fig. 2.4 shape facts, Eq. 2.20 equilibrium.
#include <gtest/gtest.h>

#include <ceres/jet.h>

#include <cmath>
#include <string>

#include "core/terramechanics/model.h"
#include "core/terramechanics/model_impl.h"
#include "terramechanics_soils.h"

using namespace roverlab::terramechanics;
using roverlab::test::ding_tyii;
using roverlab::test::kapvik_wheel;
using roverlab::test::lunar_nominal;

namespace {

// One row of an independent reference script (500-point midpoint rule) on
// the Ding wheel: sinkage to 1e-9 m, DP to 1e-6 N, torque to 1e-7 N m.
void expect_reference_row(ModelOptions o, double load, double slip, double sinkage, double drawbar, double torque,
                          const std::string& label) {
  o.integration = Integration::riemann;
  o.riemann_points = 500;
  const Wheel ding{0.15735, 0.165, 0, 0.0};
  const Traction t = evaluate(ding_tyii(), ding, load, slip, o);
  ASSERT_TRUE(t.ok()) << label;
  EXPECT_NEAR(t.sinkage, sinkage, 1e-9) << label;
  EXPECT_NEAR(t.drawbar_pull, drawbar, 1e-6) << label;
  EXPECT_NEAR(t.resistive_torque, torque, 1e-7) << label;
}

}  // namespace

TEST(Soil, WongConstantsFromBekkerModuliMatchTable22) {
  // Eq. 2.12-2.13 with the Kapvik width: Table 2.2 gives k1 = 12.0 kPa, k2 = 1845.3 kPa/m.
  EXPECT_NEAR(k1(ding_tyii(), 0.07), 12.0e3, 0.05e3);
  EXPECT_NEAR(k2(ding_tyii(), 0.07), 1845.3e3, 2e3);
}

TEST(WongReece, VerticalEquilibriumHoldsAtTheEntryAngle) {
  for (double load : {1.0, 20.0, 50.0, 150.0}) {
    for (double slip : {0.0, 0.3, 0.9}) {
      for (Integration integration : {Integration::simpson, Integration::riemann}) {
        ModelOptions o;
        o.integration = integration;
        const Traction t = evaluate(ding_tyii(), kapvik_wheel(), load, slip, o);
        ASSERT_TRUE(t.ok());
        const auto p = detail::make_params<double>(ding_tyii(), o.extensions);
        const auto in = detail::integrals<double>(p, kapvik_wheel(), o, slip, t.entry_angle);
        EXPECT_NEAR(in.normal, load, 1e-8 * load);  // Eq. 2.20
        EXPECT_NEAR(t.sinkage, 0.075 * (1.0 - std::cos(t.entry_angle)), 1e-15);
        EXPECT_NEAR(t.max_stress_angle, t.entry_angle * (0.18 + 0.32 * slip), 1e-12);  // Eq. 2.10
      }
    }
  }
}

TEST(WongReece, EntryAngleIsTheFirstRootOfEquation220) {
  ModelOptions o;
  for (const Soil& soil : {ding_tyii(), lunar_nominal()}) {
    for (double load : {5.0, 50.0}) {
      const double slip = 0.4;
      const Traction t = evaluate(soil, kapvik_wheel(), load, slip, o);
      ASSERT_TRUE(t.ok());
      const auto p = detail::make_params<double>(soil, o.extensions);
      // A fine scan from 0: the first crossing of W is where the solver stopped.
      double first = NAN;
      const int steps = 20000;
      for (int k = 1; k <= steps; ++k) {
        const double th = M_PI / 2 * k / steps;
        if (detail::integrals<double>(p, kapvik_wheel(), o, slip, th).normal >= load) {
          first = th;
          break;
        }
      }
      EXPECT_NEAR(t.entry_angle, first, M_PI / 2 / steps);
    }
  }
}

TEST(WongReece, Figure24ShapeFacts) {
  // W = 50 N, Kapvik wheel r = 75 mm, b = 70 mm, TYII soil (seed 003 Fig. 2.4).
  ModelOptions simpson, riemann;
  riemann.integration = Integration::riemann;
  const double load = 50.0;
  auto dp = [&](double s, const ModelOptions& o) {
    return evaluate(ding_tyii(), kapvik_wheel(), load, s, o).drawbar_pull;
  };
  auto tau = [&](double s, const ModelOptions& o) {
    return evaluate(ding_tyii(), kapvik_wheel(), load, s, o).resistive_torque;
  };
  // Compaction resistance: a free-rolling wheel (s = 0) is pulled back.
  EXPECT_LT(dp(0.0, simpson), 0.0);
  // Resistive torque rises with slip over the whole range [-1, 1], and is
  // negative (braking) for a strongly skidding wheel.
  double previous = -INFINITY;
  for (int k = -20; k <= 20; ++k) {
    const double s = 0.05 * k;
    const double t = tau(s, simpson);
    EXPECT_GT(t, previous) << "s = " << s;
    previous = t;
  }
  EXPECT_LT(tau(-1.0, simpson), 0.0);
  // Drawbar pull rises with slip from s = -0.8 to 0.6, crosses zero once in
  // (0, 0.3), and saturates: the gain from 0.3 to 0.6 is less than half that
  // from 0 to 0.3. (Beyond |s| = 0.8 the growing sinkage makes it fall
  // slightly: DP peaks near s = 0.8.)
  previous = -INFINITY;
  int crossings = 0;
  for (int k = -16; k <= 12; ++k) {
    const double s = 0.05 * k;
    const double d = dp(s, simpson);
    EXPECT_GT(d, previous) << "s = " << s;
    if (previous < 0.0 && d >= 0.0) {
      ++crossings;
      EXPECT_GT(s, 0.0);
      EXPECT_LT(s, 0.3);
    }
    previous = d;
  }
  EXPECT_EQ(crossings, 1);
  EXPECT_LT(dp(0.6, simpson) - dp(0.3, simpson), 0.5 * (dp(0.3, simpson) - dp(0.0, simpson)));
  // Skid is anti-symmetric about the s = 0 value (Eq. 2.26-2.27), continuous at 0.
  for (double s : {0.1, 0.5, 1.0}) {
    EXPECT_NEAR(dp(-s, simpson) + dp(s, simpson), 2.0 * dp(0.0, simpson), 1e-9);
    EXPECT_NEAR(tau(-s, simpson) + tau(s, simpson), 2.0 * tau(0.0, simpson), 1e-9);
  }
  EXPECT_NEAR(dp(-1e-6, simpson), dp(1e-6, simpson), 1e-3);
  // Simpson's five points and a 500-point Riemann sum "nearly identical".
  for (int k = -10; k <= 10; ++k) {
    const double s = 0.1 * k;
    EXPECT_NEAR(dp(s, simpson), dp(s, riemann), 0.25) << "s = " << s;
    EXPECT_NEAR(tau(s, simpson), tau(s, riemann), 0.01) << "s = " << s;
  }
}

TEST(WongReece, ReportsLoadsTheSoilCannotCarry) {
  // 600 N on the small Kapvik wheel in lunar soil needs theta0 > 90 deg.
  const Traction t = evaluate(lunar_nominal(), kapvik_wheel(), 600.0, 0.5);
  EXPECT_EQ(t.status, TractionStatus::unsupported_load);
  EXPECT_FALSE(t.ok());
  EXPECT_EQ(evaluate(ding_tyii(), kapvik_wheel(), -1.0, 0.5).status, TractionStatus::invalid_input);
  EXPECT_EQ(evaluate(ding_tyii(), kapvik_wheel(), 10.0, 1.5).status, TractionStatus::invalid_input);
  EXPECT_EQ(evaluate(ding_tyii(), kapvik_wheel(), NAN, 0.5).status, TractionStatus::invalid_input);
}

TEST(Bekker, EquilibriumAndSlipIndependence) {
  ModelOptions o;
  o.kind = ModelKind::bekker;
  o.integration = Integration::riemann;
  const Traction a = evaluate(ding_tyii(), kapvik_wheel(), 50.0, 0.1, o);
  const Traction b = evaluate(ding_tyii(), kapvik_wheel(), 50.0, 0.7, o);
  ASSERT_TRUE(a.ok());
  EXPECT_DOUBLE_EQ(a.drawbar_pull, b.drawbar_pull);  // Bekker has no slip
  const auto p = detail::make_params<double>(ding_tyii(), o.extensions);
  EXPECT_NEAR(detail::integrals<double>(p, kapvik_wheel(), o, 0.1, a.entry_angle).normal, 50.0, 1e-7);  // Eq. 2.5
  // Bekker's shear stress is c + sigma tan(phi) everywhere: more thrust than Wong-Reece at low slip.
  EXPECT_GT(a.drawbar_pull, evaluate(ding_tyii(), kapvik_wheel(), 50.0, 0.1).drawbar_pull);
}

TEST(SlipState, CasesOfTable23) {
  const double r = 0.1;
  auto st = slip_state(0.05, 1.0, r);  // r w = 0.1 > v: slipping
  EXPECT_EQ(st.table_case, 1);
  EXPECT_NEAR(st.slip, 0.5, 1e-12);  // Eq. 2.8
  EXPECT_EQ(st.direction, 1.0);
  st = slip_state(-0.05, 1.0, r);
  EXPECT_EQ(st.table_case, 2);
  EXPECT_EQ(st.slip, 1.0);
  st = slip_state(0.2, 1.0, r);  // skidding
  EXPECT_EQ(st.table_case, 3);
  EXPECT_NEAR(st.slip, -0.5, 1e-12);  // Eq. 2.9
  st = slip_state(-0.2, 1.0, r);
  EXPECT_EQ(st.table_case, 4);
  st = slip_state(-0.2, 0.0, r);
  EXPECT_EQ(st.table_case, 5);
  EXPECT_EQ(st.slip, -1.0);
  EXPECT_EQ(st.direction, -1.0);
  st = slip_state(0.0, -2.0, r);
  EXPECT_EQ(st.table_case, 6);
  EXPECT_EQ(st.slip, 1.0);
  EXPECT_EQ(st.direction, -1.0);
  EXPECT_EQ(slip_state(0.0, 0.0, r).table_case, 7);
}

TEST(Extensions, EachChangesWhatItsPhysicsSays) {
  const Wheel smooth{0.157, 0.165, 0, 0.0};
  const Wheel lugged{0.157, 0.165, 30, 0.01};
  const double load = 80.0;
  const Traction base0 = evaluate(ding_tyii(), smooth, load, 0.0);
  const Traction base5 = evaluate(ding_tyii(), smooth, load, 0.5);

  ModelOptions ss;
  ss.extensions.slip_sinkage_n1 = 0.4;
  EXPECT_DOUBLE_EQ(evaluate(ding_tyii(), smooth, load, 0.0, ss).sinkage, base0.sinkage);  // no slip, no change
  EXPECT_GT(evaluate(ding_tyii(), smooth, load, 0.5, ss).sinkage, 1.3 * base5.sinkage);

  ModelOptions gr;
  gr.extensions.grousers = true;
  EXPECT_DOUBLE_EQ(evaluate(ding_tyii(), smooth, load, 0.5, gr).drawbar_pull, base5.drawbar_pull);
  const Traction g = evaluate(ding_tyii(), lugged, load, 0.5, gr);
  EXPECT_GT(g.drawbar_pull, base5.drawbar_pull);
  EXPECT_GT(g.resistive_torque, base5.resistive_torque);

  ModelOptions bd;
  bd.extensions.bulldozing = true;
  const Traction b = evaluate(ding_tyii(), smooth, load, 0.5, bd);
  EXPECT_LT(b.drawbar_pull, base5.drawbar_pull);
  EXPECT_DOUBLE_EQ(b.resistive_torque, base5.resistive_torque);
  EXPECT_DOUBLE_EQ(b.sinkage, base5.sinkage);

  ModelOptions weak;
  weak.extensions.soil_strength = 0.7;
  const Traction w = evaluate(ding_tyii(), smooth, load, 0.5, weak);
  EXPECT_GT(w.sinkage, base5.sinkage);
  EXPECT_LT(w.drawbar_pull, base5.drawbar_pull);
}

TEST(WongReece, JetDerivativesThroughTheRootSolveMatchFiniteDifferences) {
  using J = ceres::Jet<double, 3>;
  ModelOptions o;
  o.extensions.slip_sinkage_n1 = 0.2;
  const Wheel w{0.157, 0.165, 0, 0.0};
  auto p = detail::make_params<J>(ding_tyii(), o.extensions);
  p.soil_strength = J(1.0, 0);
  p.slip_sinkage_n1 = J(0.2, 1);
  p.n = J(1.1, 2);
  const auto sol = detail::solve(p, w, o, 0.4, 80.0);
  ASSERT_EQ(sol.status, TractionStatus::ok);
  auto value = [&](double strength, double n1, double n) {
    auto q = detail::make_params<double>(ding_tyii(), o.extensions);
    q.soil_strength = strength;
    q.slip_sinkage_n1 = n1;
    q.n = n;
    const auto s = detail::solve(q, w, o, 0.4, 80.0);
    return std::array<double, 3>{s.drawbar, s.torque, s.sinkage};
  };
  const double h = 1e-6;
  const double base[3] = {1.0, 0.2, 1.1};
  for (int k = 0; k < 3; ++k) {
    double up[3] = {base[0], base[1], base[2]}, down[3] = {base[0], base[1], base[2]};
    up[k] += h;
    down[k] -= h;
    const auto a = value(up[0], up[1], up[2]);
    const auto b = value(down[0], down[1], down[2]);
    const double fd[3] = {(a[0] - b[0]) / (2 * h), (a[1] - b[1]) / (2 * h), (a[2] - b[2]) / (2 * h)};
    EXPECT_NEAR(sol.drawbar.v[k], fd[0], 1e-4 * (1.0 + std::abs(fd[0]))) << "parameter " << k;
    EXPECT_NEAR(sol.torque.v[k], fd[1], 1e-4 * (1.0 + std::abs(fd[1]))) << "parameter " << k;
    EXPECT_NEAR(sol.sinkage.v[k], fd[2], 1e-4 * (1e-3 + std::abs(fd[2]))) << "parameter " << k;
  }
}

// Issue 33 item 4: the rear angle (theta_r = -kappa theta_f) and the
// slip-dependent shear modulus (K = K0 (1 + k_s s)) against values computed
// independently by tests/data/single_wheel/extensions_reference.py (plain
// Python from the equations, 500-point midpoint rule, bisection):
//   load, slip, kappa, k_s: sinkage_m, DP_N, torque_Nm
TEST(Extensions, RearAngleAndSlipShearModulusMatchAnIndependentCalculation) {
  struct Row {
    double load, slip, kappa, k_s, sinkage, drawbar, torque;
  };
  const Row rows[] = {
      {80, 0.3, 0.00, 0.0, 0.0100328534, 16.4327451, 4.51488392},
      {80, 0.3, 0.25, 0.0, 0.00878266777, 20.9293363, 4.74458601},
      {80, 0.1, 0.00, 3.0, 0.00982932957, 0.669467752, 1.96166012},
      {120, 0.6, 0.40, 1.5, 0.0112965077, 34.3207792, 7.72100403},
      {40, 0.0, 0.20, 2.0, 0.00562739435, -2.58237325, 0.162904908},
  };
  const Wheel ding{0.15735, 0.165, 0, 0.0};
  for (const Row& r : rows) {
    ModelOptions o;
    o.extensions.rear_angle_ratio = r.kappa;
    o.extensions.shear_modulus_slip = r.k_s;
    expect_reference_row(
        o, r.load, r.slip, r.sinkage, r.drawbar, r.torque,
        std::to_string(r.load) + " N, s " + std::to_string(r.slip) + ", kappa " + std::to_string(r.kappa));
  }
  // The rear contact carries part of the load behind the bottom: less sinkage
  // and more pull at the same slip (row 2 against row 1); a stiffer shear
  // modulus at higher slip builds thrust more slowly (row 3 against the
  // baseline, 3.57 N at 80 N, s = 0.1). With Simpson too.
  const Traction base = evaluate(ding_tyii(), ding, 80.0, 0.1);
  ModelOptions stiff;
  stiff.extensions.shear_modulus_slip = 3.0;
  EXPECT_LT(evaluate(ding_tyii(), ding, 80.0, 0.1, stiff).drawbar_pull, base.drawbar_pull - 2.0);
  EXPECT_DOUBLE_EQ(evaluate(ding_tyii(), ding, 80.0, 0.0, stiff).drawbar_pull,
                   evaluate(ding_tyii(), ding, 80.0, 0.0).drawbar_pull);  // no slip, no change
  ModelOptions rear;
  rear.extensions.rear_angle_ratio = 0.25;
  const Traction tr = evaluate(ding_tyii(), ding, 80.0, 0.3, rear);
  const Traction t0 = evaluate(ding_tyii(), ding, 80.0, 0.3);
  EXPECT_LT(tr.sinkage, t0.sinkage);
  EXPECT_GT(tr.drawbar_pull, t0.drawbar_pull + 2.0);
}

// Issue 33 item 4: Wong's peaked ("hump") shear curve of dense sand,
// tau / tau_max = K_r [1 + (1 / (K_r (1 - 1/e)) - 1) e^(1 - x)] (1 - e^-x),
// x = j / K_w, against tests/data/single_wheel/shear_peak_reference.py (plain
// Python from the printed formula): tau_max exactly at x = 1, K_r tau_max far
// out, and its maximum at x = 1 only for K_r = e (e - 2) / (e - 1)^2 = 0.6613;
// elsewhere the curve passes tau_max at K_w and peaks nearby, a little above:
//   K_r: argmax x, max tau / tau_max
TEST(ShearPeak, TheCurveMatchesAnIndependentCalculation) {
  struct Row {
    double k_r, argmax, max;
  };
  const double e = std::exp(1.0);
  const Row rows[] = {{0.3, 0.7832, 1.027650},
                      {0.5, 0.8795, 1.006530},
                      {e * (e - 2.0) / ((e - 1.0) * (e - 1.0)), 1.0000, 1.000000},
                      {0.8, 1.1653, 1.006680},
                      {1.0, 1.6931, 1.053524}};
  for (const Row& r : rows) {
    EXPECT_NEAR(detail::peaked_shear(1.0, r.k_r), 1.0, 1e-12) << r.k_r;
    EXPECT_NEAR(detail::peaked_shear(50.0, r.k_r), r.k_r, 1e-12) << r.k_r;
    double best_x = 0.0, best = 0.0;
    for (int i = 1; i < 500000; ++i) {
      const double v = detail::peaked_shear(i * 1e-5, r.k_r);
      if (v > best) {
        best = v;
        best_x = i * 1e-5;
      }
    }
    EXPECT_NEAR(best_x, r.argmax, 1e-4) << r.k_r;
    EXPECT_NEAR(best, r.max, 1e-6) << r.k_r;
  }
}

// The wheel with the peaked curve in place of Eq. 2.19 (K_w scaled by
// 1 + k_s s) against the same script (500-point midpoint rule, bisection):
//   load, slip, K_r, K_w, k_s: sinkage_m, DP_N, torque_Nm
TEST(ShearPeak, TheWheelMatchesAnIndependentCalculationAndIsOffByDefault) {
  struct Row {
    double load, slip, k_r, k_w, k_s, sinkage, drawbar, torque;
  };
  const Row rows[] = {
      {80, 0.1, 0.6, 0.008, 0.0, 0.00952352823, 29.6775127, 6.46063506},
      {80, 0.3, 0.6, 0.008, 0.0, 0.00978777449, 32.3899829, 6.98017323},
      {80, 0.6, 0.4, 0.004, 0.0, 0.0107066495, 10.7594114, 3.82300543},
      {120, 0.2, 0.9, 0.020, 1.5, 0.0126401645, 24.3700021, 7.01758669},
      {40, 0.0, 0.7, 0.010, 0.0, 0.006281844, -0.67513623, 0.621152229},
  };
  const Wheel ding{0.15735, 0.165, 0, 0.0};
  for (const Row& r : rows) {
    ModelOptions o;
    o.extensions.shear_peak = true;
    o.extensions.shear_residual_ratio = r.k_r;
    o.extensions.shear_peak_displacement = r.k_w;
    o.extensions.shear_modulus_slip = r.k_s;
    expect_reference_row(o, r.load, r.slip, r.sinkage, r.drawbar, r.torque,
                         std::to_string(r.load) + " N, s " + std::to_string(r.slip) + ", K_r " + std::to_string(r.k_r));
  }
  // Switched off, its parameters change nothing: the baseline bit for bit.
  ModelOptions off;
  off.extensions.shear_residual_ratio = 0.3;
  off.extensions.shear_peak_displacement = 0.001;
  for (Integration integration : {Integration::simpson, Integration::riemann}) {
    for (double slip : {-0.4, 0.0, 0.3}) {
      ModelOptions base;
      base.integration = off.integration = integration;
      const Traction a = evaluate(ding_tyii(), ding, 80.0, slip, off),
                     b = evaluate(ding_tyii(), ding, 80.0, slip, base);
      EXPECT_EQ(a.drawbar_pull, b.drawbar_pull);
      EXPECT_EQ(a.resistive_torque, b.resistive_torque);
      EXPECT_EQ(a.sinkage, b.sinkage);
    }
  }
}

// Soil identification differentiates through it: the Jets' derivatives with
// respect to K_r and K_w equal central differences.
TEST(ShearPeak, JetDerivativesMatchFiniteDifferences) {
  using J = ceres::Jet<double, 2>;
  ModelOptions o;
  o.extensions.shear_peak = true;
  const Wheel w{0.157, 0.165, 0, 0.0};
  auto p = detail::make_params<J>(ding_tyii(), o.extensions);
  p.shear_residual_ratio = J(0.6, 0);
  p.shear_peak_displacement = J(0.008, 1);
  const auto sol = detail::solve(p, w, o, 0.3, 80.0);
  ASSERT_EQ(sol.status, TractionStatus::ok);
  auto drawbar = [&](double k_r, double k_w) {
    auto q = detail::make_params<double>(ding_tyii(), o.extensions);
    q.shear_residual_ratio = k_r;
    q.shear_peak_displacement = k_w;
    return detail::solve(q, w, o, 0.3, 80.0).drawbar;
  };
  const double d_kr = (drawbar(0.6 + 1e-6, 0.008) - drawbar(0.6 - 1e-6, 0.008)) / 2e-6;
  const double d_kw = (drawbar(0.6, 0.008 + 1e-8) - drawbar(0.6, 0.008 - 1e-8)) / 2e-8;
  EXPECT_NEAR(sol.drawbar.v[0], d_kr, 1e-4 * (1.0 + std::abs(d_kr)));
  EXPECT_NEAR(sol.drawbar.v[1], d_kw, 1e-4 * (1.0 + std::abs(d_kw)));
  EXPECT_GT(std::abs(d_kw), 100.0);  // K_w matters: not a vacuous comparison
}
