// The granular resistive-force model family (core/terramechanics/rft.h):
// Li et al. 2013's generic stresses, the wheel mesh, the sinkage balance and
// published qualitative properties. The element sums against an independent
// Python implementation are the ctest rft_reference (tests/data/rft).
#include <gtest/gtest.h>

#include <cmath>
#include <numeric>
#include <thread>

#include "core/terramechanics/model.h"
#include "core/terramechanics/rft.h"
#include "core/terramechanics/slip_angle_model.h"

namespace {

using namespace roverlab::terramechanics;
constexpr double kPi = 3.14159265358979323846;

Soil sand(double zeta = 2.0e6) {
  Soil s;
  s.name = "rft test sand";
  s.rft_scale = zeta;
  return s;
}

Wheel smooth() { return Wheel{0.0625, 0.06, 0, 0.0}; }

ModelOptions rft(SlipDefinition d = SlipDefinition::travel) {
  ModelOptions o;
  o.kind = ModelKind::rft;
  o.slip_definition = d;
  return o;
}

double deg(double d) { return d * kPi / 180.0; }

TEST(RftAlpha, GenericFitIsNormalisedOnAPlatePushedStraightDown) {
  // Li 2013: zeta is alpha_z of a horizontal plate moving down; the generic fit has 1 there and no alpha_x.
  const Alpha a = generic_alpha(0.0, kPi / 2.0);
  EXPECT_NEAR(a.z, 1.0, 1e-12);
  EXPECT_NEAR(a.x, 0.0, 1e-12);
  // Penetration resists more than extraction, and a plate dragged flat is lifted (Ding et al. 2011, PRL).
  EXPECT_LT(generic_alpha(0.0, -kPi / 2.0).z, 0.0);
  EXPECT_GT(generic_alpha(0.0, 0.0).z, 0.3);
}

TEST(RftAlpha, MirrorImageFlipsAlphaXAndKeepsAlphaZ) {
  for (double beta : {-1.2, -0.4, 0.0, 0.3, 1.1}) {
    for (double gamma : {-1.4, -0.5, 0.0, 0.7, 1.5}) {
      const Alpha a = generic_alpha(beta, gamma), m = generic_alpha(-beta, kPi - gamma);
      EXPECT_NEAR(m.x, -a.x, 1e-12) << beta << " " << gamma;
      EXPECT_NEAR(m.z, a.z, 1e-12) << beta << " " << gamma;
    }
  }
}

TEST(RftElement, PlateStressIsDepthTimesAlphaOnItsArea) {
  // A horizontal plate (outward normal down) pushed down: zeta d A upward per unit zeta and depth.
  const RftElement plate{0, 0, 0, 0, 0, -1, 2e-4, RftPart::rim};
  const Vec3 f = rft_element_stress(plate, {0, 0, -3.0});  // rate independent: speed 3
  EXPECT_NEAR(f.z, 2e-4, 1e-15);
  EXPECT_NEAR(f.x, 0.0, 1e-15);
  // A vertical plate facing +x pushed along +x: drag C01 - C11 - C-11 = 0.370, against the motion.
  const RftElement wall{0, 0, 0, 1, 0, 0, 1.0, RftPart::side};
  EXPECT_NEAR(rft_element_stress(wall, {1, 0, 0}).x, -0.370, 1e-12);
  // The same wall moved along -x trails: no stress.
  EXPECT_EQ(rft_element_stress(wall, {-1, 0, 0}).x, 0.0);
  // A wall facing +y pushed along +y: the same drag along -y (the 3D decomposition is rotation invariant).
  const RftElement side{0, 0, 0, 0, 1, 0, 1.0, RftPart::side};
  EXPECT_NEAR(rft_element_stress(side, {0, 1, 0}).y, -0.370, 1e-12);
}

TEST(RftMesh, AreasAreTheLowerHalfOfRimSidesAndGrousers) {
  const Wheel w = smooth();
  const auto mesh = rft_wheel_mesh(w);
  EXPECT_EQ(mesh.size(), 90u * 8u + 2u * 90u * 6u);
  double rim = 0, side = 0;
  for (const auto& e : mesh) (e.part == RftPart::rim ? rim : side) += e.area;
  EXPECT_NEAR(rim, kPi * w.radius * w.width, 1e-12);
  EXPECT_NEAR(side, kPi * w.radius * w.radius, 1e-12);  // two half discs
  Wheel g = w;
  g.grouser_count = 12;
  g.grouser_height = 0.005;
  double grousers = 0;
  for (const auto& e : rft_wheel_mesh(g, 2.0)) grousers += e.part == RftPart::grouser ? e.area : 0.0;
  // Half the grousers (averaged over phases) in the lower half, two faces each, height scaled by 2.
  EXPECT_NEAR(grousers, 6.0 * 2.0 * 0.010 * w.width, 1e-12);
}

TEST(RftWheel, LoadIsCarriedAndForcesScaleWithZetaAtTheSameSinkage) {
  // Stress is linear in zeta: zeta k and load k give the same sinkage and k times every force.
  for (double beta : {0.0, 30.0, 75.0}) {
    for (double slip : {-0.6, 0.0, 0.4}) {
      const auto a = evaluate_slip_angle(sand(1e6), smooth(), 15.0, slip, deg(beta), rft());
      const auto b = evaluate_slip_angle(sand(3e6), smooth(), 45.0, slip, deg(beta), rft());
      ASSERT_TRUE(a.ok() && b.ok());
      EXPECT_NEAR(b.sinkage, a.sinkage, 1e-12);
      EXPECT_NEAR(b.drawbar_pull, 3.0 * a.drawbar_pull, 1e-9);
      EXPECT_NEAR(b.lateral_force, 3.0 * a.lateral_force, 1e-9);
      EXPECT_NEAR(b.resistive_torque, 3.0 * a.resistive_torque, 1e-10);
    }
  }
  // Heavier loads sink deeper.
  double previous = 0.0;
  for (double load : {5.0, 10.0, 20.0, 40.0}) {
    const auto t = evaluate_slip_angle(sand(), smooth(), load, 0.2, 0.0, rft());
    ASSERT_TRUE(t.ok());
    EXPECT_GT(t.sinkage, previous);
    EXPECT_NEAR(std::cos(t.entry_angle), 1.0 - t.sinkage / 0.0625, 1e-12);
    previous = t.sinkage;
  }
}

TEST(RftWheel, StraightDrivingHasNoLateralForceAndMirrorsWithTheSlipAngle) {
  const auto straight = evaluate_slip_angle(sand(), smooth(), 20.0, 0.3, 0.0, rft());
  ASSERT_TRUE(straight.ok());
  EXPECT_NEAR(straight.lateral_force, 0.0, 1e-12);
  const Traction t = evaluate(sand(), smooth(), 20.0, 0.3, rft());  // evaluate() is slip angle 0
  EXPECT_EQ(t.drawbar_pull, straight.drawbar_pull);
  EXPECT_EQ(t.sinkage, straight.sinkage);
  const auto left = evaluate_slip_angle(sand(), smooth(), 20.0, 0.3, deg(40), rft());
  const auto right = evaluate_slip_angle(sand(), smooth(), 20.0, 0.3, deg(-40), rft());
  EXPECT_LT(left.lateral_force, 0.0);  // resists the motion along +y
  EXPECT_NEAR(right.lateral_force, -left.lateral_force, 1e-9);
  EXPECT_NEAR(right.drawbar_pull, left.drawbar_pull, 1e-9);
}

TEST(RftWheel, DrawbarPullRisesWithSlipAndATowedWheelResists) {
  // Agarwal et al. 2019 (rigid wheels in dry sand): DP increases with slip, negative near zero slip.
  double previous = -1e9;
  for (double slip : {0.0, 0.2, 0.4, 0.6, 0.8}) {
    const auto t = evaluate_slip_angle(sand(), smooth(), 20.0, slip, 0.0, rft());
    ASSERT_TRUE(t.ok());
    EXPECT_GT(t.drawbar_pull, previous) << slip;
    previous = t.drawbar_pull;
  }
  EXPECT_LT(evaluate_slip_angle(sand(), smooth(), 20.0, 0.0, 0.0, rft()).drawbar_pull, 0.0);
  // Braking (travel slip below 0): the soil pushes back.
  EXPECT_LT(evaluate_slip_angle(sand(), smooth(), 20.0, -0.6, 0.0, rft()).drawbar_pull, -1.0);
}

TEST(RftWheel, LateralForceRisesWithSlipAngleTo90Degrees) {
  // A wheel towed (travel slip 0) at growing slip angles: |F_y| rises to 75 deg and holds to 90 deg, where the
  // side face bulldozes (the trend of Agarwal 2019's 3D RFT; the notes: measured |F_y| keeps rising
  // while a flat-surface RFT levels off there).
  double previous = 0.0, at75 = 0.0;
  for (double beta = 15.0; beta <= 75.0; beta += 15.0) {
    const auto t = evaluate_slip_angle(sand(), smooth(), 20.0, 0.0, deg(beta), rft());
    ASSERT_TRUE(t.ok());
    EXPECT_GT(std::abs(t.lateral_force), previous) << beta;
    previous = at75 = std::abs(t.lateral_force);
  }
  const auto at90 = evaluate_slip_angle(sand(), smooth(), 20.0, 0.0, deg(90), rft());
  EXPECT_GT(std::abs(at90.lateral_force), 0.97 * at75);
  EXPECT_GT(std::abs(at90.lateral_force), 0.3 * 20.0);  // a sizeable share of the load
  // 90 deg is the limit of 89.99 deg.
  const auto near90 = evaluate_slip_angle(sand(), smooth(), 20.0, 0.0, deg(89.99), rft());
  EXPECT_NEAR(at90.lateral_force, near90.lateral_force, 0.01 * std::abs(at90.lateral_force));
}

TEST(RftWheel, PileUpAndDepthScaleAreNeutralAtZeroAndDeepenTheForces) {
  ModelOptions o = rft();
  const auto flat = evaluate_slip_angle(sand(), smooth(), 20.0, 0.2, deg(60), o);
  o.extensions.rft_pileup = 0.0;
  o.extensions.rft_depth_scale = 0.0;
  const auto neutral = evaluate_slip_angle(sand(), smooth(), 20.0, 0.2, deg(60), o);
  EXPECT_EQ(neutral.lateral_force, flat.lateral_force);
  o.extensions.rft_pileup = 0.8;
  const auto piled = evaluate_slip_angle(sand(), smooth(), 20.0, 0.2, deg(60), o);
  ASSERT_TRUE(piled.ok());
  // Sand heaped against the side face: more lateral resistance at the same load, less sinkage.
  EXPECT_GT(std::abs(piled.lateral_force), std::abs(flat.lateral_force));
  EXPECT_LT(piled.sinkage, flat.sinkage);
}

TEST(RftWheel, GrousersAddThrustAndTheirHeightScaleActs) {
  Wheel g = smooth();
  g.grouser_count = 12;
  g.grouser_height = 0.005;
  const auto plain = evaluate_slip_angle(sand(), smooth(), 20.0, 0.3, 0.0, rft());
  const auto lugged = evaluate_slip_angle(sand(), g, 20.0, 0.3, 0.0, rft());
  ASSERT_TRUE(plain.ok() && lugged.ok());
  EXPECT_GT(lugged.drawbar_pull, plain.drawbar_pull);
  ModelOptions o = rft();
  o.extensions.grousers = true;
  o.extensions.grouser_effectiveness = 0.0;  // height scaled to nothing: the smooth wheel
  const auto none = evaluate_slip_angle(sand(), g, 20.0, 0.3, 0.0, o);
  EXPECT_NEAR(none.drawbar_pull, plain.drawbar_pull, 1e-9);
}

TEST(RftWheel, BadInputIsAStatusNotACrash) {
  EXPECT_EQ(evaluate_slip_angle(sand(), smooth(), -1.0, 0.2, 0.0, rft()).status, TractionStatus::invalid_input);
  EXPECT_EQ(evaluate_slip_angle(sand(), smooth(), 20.0, 1.5, 0.0, rft()).status, TractionStatus::invalid_input);
  EXPECT_EQ(evaluate_slip_angle(sand(), smooth(), 20.0, 0.2, 2.0, rft()).status, TractionStatus::invalid_input);
  EXPECT_EQ(evaluate_slip_angle(sand(0.0), smooth(), 20.0, 0.2, 0.0, rft()).status, TractionStatus::invalid_input);
  EXPECT_EQ(evaluate_slip_angle(sand(NAN), smooth(), 20.0, 0.2, 0.0, rft()).status, TractionStatus::invalid_input);
  // More than half the wheel would have to sink: unsupported, as the other families say it.
  EXPECT_EQ(evaluate_slip_angle(sand(1e4), smooth(), 500.0, 0.2, 0.0, rft()).status, TractionStatus::unsupported_load);
}

// An evaluation that is bit for bit another (both ok): every output.
void expect_bit_identical(const SlipAngleTraction& again, const SlipAngleTraction& fresh, int k) {
  ASSERT_TRUE(fresh.ok() && again.ok()) << k;
  EXPECT_EQ(again.drawbar_pull, fresh.drawbar_pull) << k;
  EXPECT_EQ(again.lateral_force, fresh.lateral_force) << k;
  EXPECT_EQ(again.resistive_torque, fresh.resistive_torque) << k;
  EXPECT_EQ(again.sinkage, fresh.sinkage) << k;
}

// Each thread keeps the stresses of the motions it met (rft.cpp): a point
// evaluated after many others, other wheels, pile-ups and depth scales among
// them, is bit for bit what a fresh thread computes for it.
TEST(RftWheel, AnEvaluationIsTheSameAfterOthersAsOnAFreshThread) {
  Wheel g = smooth();
  g.grouser_count = 12;
  g.grouser_height = 0.005;
  ModelOptions piled = rft();
  piled.extensions.rft_pileup = 0.4;
  piled.extensions.rft_depth_scale = 0.3;
  const auto point = [&](const Wheel& w, const ModelOptions& o) {
    return evaluate_slip_angle(sand(2.3e6), w, 21.0, 0.35, deg(40.0), o);
  };
  SlipAngleTraction fresh[3];
  std::thread([&] {
    fresh[0] = point(smooth(), rft());
    fresh[1] = point(g, rft());
    fresh[2] = point(smooth(), piled);
  }).join();
  for (int i = 0; i < 400; ++i) {  // other slips, angles, loads, scales, wheels and pile-ups
    ModelOptions o = rft(i % 3 == 0 ? SlipDefinition::longitudinal : SlipDefinition::travel);
    o.extensions.rft_pileup = (i % 4) * 0.2;
    const bool same_motion = i % 5 == 0;  // the points' slip and angle, read another way or with another wheel
    (void)evaluate_slip_angle(sand(1.5e6 + 1e4 * i), i % 2 != 0 ? g : smooth(), 10.0 + i % 30,
                              same_motion ? 0.35 : -0.9 + 0.0045 * i, deg(same_motion ? 40.0 : i % 91), o);
  }
  // The piled point's motion at other pile-ups, near (a fit's steps: the
  // cached order mended) and far (sorted afresh), last one near its own.
  for (const double p : {0.41, 0.39, 3.0, 9.5, 0.0, 2.0, 0.4001}) {
    ModelOptions o = piled;
    o.extensions.rft_pileup = p;
    (void)point(smooth(), o);
  }
  const SlipAngleTraction again[3] = {point(smooth(), rft()), point(g, rft()), point(smooth(), piled)};
  for (int k = 0; k < 3; ++k) expect_bit_identical(again[k], fresh[k], k);
  EXPECT_NE(fresh[0].drawbar_pull, fresh[1].drawbar_pull);  // the three points differ
  EXPECT_NE(fresh[0].sinkage, fresh[2].sinkage);
}

// Past their budgets the caches drop what was used least recently (issue 46:
// starting over made two fits side by side build each other's lists again):
// after 40 grouser heights (the mesh cache holds 16) and 3,000 motions
// (more elements than the lists' budget of 2^21), each point asked for
// between them is still what a fresh thread computes.
TEST(RftWheel, AnEvaluationIsTheSameAfterTheCachesMadeRoom) {
  Wheel g = smooth();
  g.grouser_count = 12;
  g.grouser_height = 0.005;
  ModelOptions grousered = rft();
  grousered.extensions.grousers = true;
  const auto point = [&](const Wheel& w, const ModelOptions& o) {
    return evaluate_slip_angle(sand(2.3e6), w, 21.0, 0.35, deg(40.0), o);
  };
  SlipAngleTraction fresh[2];
  std::thread([&] {
    fresh[0] = point(smooth(), rft());
    fresh[1] = point(g, grousered);
  }).join();
  for (int i = 0; i < 3000; ++i) {
    ModelOptions o = grousered;
    o.extensions.grouser_effectiveness = 0.5 + (i % 40) * 0.025;  // 40 meshes of the grousered wheel
    (void)evaluate_slip_angle(sand(), i % 2 != 0 ? g : smooth(), 20.0, -0.9 + 0.0006 * i, deg(i % 91), o);
    if (i % 500 == 0) {
      EXPECT_EQ(point(g, grousered).drawbar_pull, fresh[1].drawbar_pull) << i;
      EXPECT_EQ(point(smooth(), rft()).sinkage, fresh[0].sinkage) << i;
    }
  }
  const SlipAngleTraction again[2] = {point(smooth(), rft()), point(g, grousered)};
  for (int k = 0; k < 2; ++k) expect_bit_identical(again[k], fresh[k], k);
  EXPECT_NE(fresh[0].drawbar_pull, fresh[1].drawbar_pull);
}

}  // namespace
