// Net-traction estimation of seed 003 chapter 5: Estimators 1-3 against the
// planar rocker-bogie simulation's truth, the rebuilt traction surfaces
// against the true local model, the observability of Appendix D, and bad
// input refused.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <iostream>
#include <map>
#include <random>

#include <Eigen/Dense>

#include "core/common/error.h"
#include "core/estimation/net_traction/net_traction.h"
#include "core/estimation/net_traction/surface.h"
#include "core/filters/fixed_unscented_filter.h"
#include "core/filters/nonlinear_filter.h"
#include "core/simulation/rocker_bogie.h"
#include "core/simulation/rocker_bogie_dynamics.h"
#include "importers/soil_file.h"

using namespace roverlab;
namespace nt = estimation::net_traction;
namespace gen = estimation::net_traction::general;
namespace wf = estimation::net_traction::wheel_force;

namespace {

// The rolling terrain of Eq. 4.51 on TYII made 2.5 times stronger, so the
// rover traverses it (docs/validation/simulation.md).
// Each test runs in its own process (gtest_discover_tests): only the
// surface test simulates the whole 200 s; the others take shorter runs.
simulation::RockerBogieRun rolling_run(int seconds, simulation::TractionSource traction) {
  simulation::RockerBogieRun run;
  run.soil = io::load_soil(std::string(ROVERLAB_RESOURCES_DIR) + "/soils/ding_tyii.json");
  run.path = simulation::rolling_path();
  run.effects.soil_strength = 2.5;
  run.duration = seconds;
  run.traction = traction;
  return run;
}

const log::Log& rolling_log(int seconds, simulation::TractionSource traction = simulation::TractionSource::polynomial) {
  static std::map<std::pair<int, simulation::TractionSource>, log::Log> logs;
  const auto key = std::make_pair(seconds, traction);
  auto it = logs.find(key);
  if (it == logs.end())
    it = logs.emplace(key, simulation::simulate_rocker_bogie({}, {}, rolling_run(seconds, traction)).log).first;
  return it->second;
}

const estimation::NetTractionResult& rolling_result(int seconds) {
  static std::map<int, estimation::NetTractionResult> results;
  auto it = results.find(seconds);
  if (it == results.end())
    it = results.emplace(seconds, estimation::run_net_traction(rolling_log(seconds), {}, {})).first;
  return it->second;
}

}  // namespace

// RMS errors per wheel over the first 100 s of the run after 5 s of
// convergence (docs/validation/net-traction.md has the 200 s figures;
// bounds about 1.5x them).
TEST(NetTraction, EstimatesTrackTheTruth) {
  const auto& r = rolling_result(100);
  const auto two = estimation::tracking_errors(rolling_log(100), r, r.two_axis);
  const auto one = estimation::tracking_errors(rolling_log(100), r, r.single_axis);
  ASSERT_TRUE(two.has_truth);
  ASSERT_TRUE(one.has_truth);
  for (int i = 0; i < 3; ++i) {
    EXPECT_LT(two.resistive_torque(i), 2e-3) << i;  // N m, of torques up to 2 N m
    EXPECT_LT(two.slip(i), 0.012) << i;
    EXPECT_LT(two.normal_load(i), 0.15) << i;    // N, of 35-66 N
    EXPECT_LT(two.drawbar_pull(i), 0.9) << i;    // N, of -5..15 N
    EXPECT_LT(two.contact_angle(i), 0.02) << i;  // rad
    EXPECT_LT(one.normal_load(i), 0.2) << i;
  }
  // Single-axis: wheel 1 (alone on the rocker) as well as with two-axis
  // sensors; wheels 2 and 3 share their bogie's perpendicular load in
  // proportion to their loads (Eq. 5.66), worse, as the seed says.
  EXPECT_LT(one.drawbar_pull(0), 0.9);
  EXPECT_LT(one.drawbar_pull(1), 3.0);
  EXPECT_LT(one.drawbar_pull(2), 3.0);
  EXPECT_GT(one.drawbar_pull(1), two.drawbar_pull(1));
}

namespace {

// Central-difference Jacobian of g at x (relative steps).
template <typename G>
Eigen::MatrixXd jacobian(const G& g, const Eigen::VectorXd& x, Eigen::Index rows) {
  Eigen::MatrixXd J(rows, x.size());
  Eigen::VectorXd a(rows), b(rows);
  for (Eigen::Index c = 0; c < x.size(); ++c) {
    const double h = 1e-6 * std::max(1.0, std::abs(x(c)));
    Eigen::VectorXd xp = x, xm = x;
    xp(c) += h;
    xm(c) -= h;
    g(xp, a);
    g(xm, b);
    J.col(c) = (a - b) / (2 * h);
  }
  return J;
}

// Appendix D (Eq. D.3): the linearised observability matrix [H; H F; ...;
// H F^(n-1)] with the measurement rows `kept`; its rank and the states its
// null space reaches (those that lose observability).
struct Observability {
  int rank = 0;
  std::vector<int> lost;
};
Observability observability(const Eigen::MatrixXd& F, const Eigen::MatrixXd& H_all, const std::vector<int>& kept) {
  const Eigen::Index n = F.cols();
  Eigen::MatrixXd H(static_cast<Eigen::Index>(kept.size()), n);
  for (std::size_t r = 0; r < kept.size(); ++r) H.row(static_cast<Eigen::Index>(r)) = H_all.row(kept[r]);
  Eigen::MatrixXd E(H.rows() * n, n);
  Eigen::MatrixXd Fk = Eigen::MatrixXd::Identity(n, n);
  for (Eigen::Index k = 0; k < n; ++k) {
    E.middleRows(k * H.rows(), H.rows()) = H * Fk;
    Fk = F * Fk;
  }
  // Scale each state (column) and each row: the rank is unchanged, the units no longer matter.
  for (Eigen::Index c = 0; c < n; ++c) {
    const double s = E.col(c).norm();
    if (s > 0) E.col(c) /= s;
  }
  for (Eigen::Index r = 0; r < E.rows(); ++r) {
    const double s = E.row(r).norm();
    if (s > 0) E.row(r) /= s;
  }
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(E, Eigen::ComputeFullV);
  const Eigen::VectorXd& sv = svd.singularValues();
  Observability o;
  for (Eigen::Index i = 0; i < sv.size(); ++i) o.rank += sv(i) > 1e-7 * sv(0) ? 1 : 0;
  const Eigen::MatrixXd null = svd.matrixV().rightCols(n - o.rank);
  for (Eigen::Index c = 0; c < n; ++c) {
    if (null.rows() > 0 && null.cols() > 0 && null.row(c).norm() > 1e-3) o.lost.push_back(static_cast<int>(c));
  }
  return o;
}

std::vector<int> all_but(int n, const std::vector<int>& dropped) {
  std::vector<int> v;
  for (int i = 0; i < n; ++i) {
    if (std::find(dropped.begin(), dropped.end(), i) == dropped.end()) v.push_back(i);
  }
  return v;
}

}  // namespace

TEST(NetTraction, Estimator1IsObservableAlongTheRunAndLosesTheSlipsAtStandstill) {
  const auto& r = rolling_result(20);
  nt::RoverConstants rover;
  nt::GeneralProcessModel f(rover, 0.02);
  const nt::GeneralMeasurementModel h;
  const auto fx = [&](const Eigen::VectorXd& x, Eigen::VectorXd& out) { f(x, out); };
  const auto hx = [&](const Eigen::VectorXd& x, Eigen::VectorXd& out) { h(x, out); };
  for (Eigen::Index k = 250; k < r.general.state.rows(); k += 500) {  // every 10 s along the run
    const Eigen::VectorXd x = r.general.state.row(k).transpose();
    const Eigen::MatrixXd F = jacobian(fx, x, gen::kStates), H = jacobian(hx, x, gen::kMeasurements);
    const Observability moving = observability(F, H, all_but(gen::kMeasurements, {}));
    EXPECT_EQ(moving.rank, 22) << "t = " << r.time[static_cast<std::size_t>(k)];
    // Standing: no slip is measured (Eq. 5.42 needs motion).
    const Observability standing = observability(F, H, all_but(gen::kMeasurements, {8, 9, 10}));
    EXPECT_EQ(standing.rank, 19);
    EXPECT_EQ(standing.lost, (std::vector<int>{gen::kSlip, gen::kSlip + 1, gen::kSlip + 2}));
  }
}

TEST(NetTraction, WheelForceEstimatorsLoseTheForceSplitAtStandstillAndTheContactAngleOffTheGround) {
  const auto& r = rolling_result(20);
  nt::ForceMeasurementModel h;
  const auto hx = [&](const Eigen::VectorXd& x, Eigen::VectorXd& out) { h(x, out); };
  const Eigen::MatrixXd F = Eigen::MatrixXd::Identity(wf::kStates, wf::kStates);  // Eq. 5.50-5.52
  for (Eigen::Index k = 250; k < r.two_axis.state.rows(); k += 500) {
    const Eigen::VectorXd g = r.general.state.row(k).transpose();
    h.set_sensor_angles(nt::sensor_angles(g(gen::kPitch), g(gen::kBogie)));
    Eigen::VectorXd x = r.two_axis.state.row(k).transpose();
    const Observability moving = observability(F, jacobian(hx, x, wf::kMeasurements), all_but(9, {}));
    EXPECT_EQ(moving.rank, 9);
    // Standing: no contact angle is measured (Eq. 5.56 needs motion). The
    // sensed force of each wheel stays known but not its split into load and
    // drawbar pull: all nine states lose observability, six combinations remain.
    const Observability standing = observability(F, jacobian(hx, x, wf::kMeasurements), all_but(9, {0, 1, 2}));
    EXPECT_EQ(standing.rank, 6);
    EXPECT_EQ(standing.lost.size(), 9u);
    // Wheel 1 off the ground: no load, no drawbar pull, its contact angle not measured.
    x(wf::kNormalLoad) = x(wf::kDrawbarPull) = 0.0;
    const Observability lifted = observability(F, jacobian(hx, x, wf::kMeasurements), all_but(9, {0}));
    EXPECT_EQ(lifted.rank, 8);
    EXPECT_EQ(lifted.lost, (std::vector<int>{wf::kContactAngle}));
  }
}

// The estimators run on fixed-size filters (bench/net_traction_bench.cpp):
// the same transform as the generic UKF (nonlinear_filter.h) with additive
// noises, so both must give the same estimates up to rounding over a stretch
// of the run (Estimator 1's 22 states; Estimators 2 and 3's identity process).
TEST(NetTraction, FixedSizeFiltersGiveTheGenericUkfsEstimates) {
  const auto& r = rolling_result(20);
  nt::RoverConstants rover;
  nt::GeneralProcessModel f(rover, 0.02);
  f.set_torques(Eigen::Vector3d(0.6, 0.5, 0.55));
  const nt::GeneralMeasurementModel h;
  nt::ForceMeasurementModel hw;
  hw.set_sensor_angles(Eigen::Vector3d(0.05, 0.1, 0.1));
  const auto same = [](const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
    return (a - b).norm() <= 1e-9 * (1.0 + b.norm());
  };
  estimation::FixedUnscentedFilter<gen::kStates, gen::kMeasurements> fixed;
  estimation::UnscentedKalmanFilter generic;
  estimation::FixedUnscentedFilter<wf::kStates, wf::kMeasurements> fixed_w;
  estimation::UnscentedKalmanFilter generic_w;
  generic.additive_measurement_noise = generic_w.additive_measurement_noise = true;
  fixed.copied_state = gen::kCopiedStates;
  const Eigen::Index k0 = 250;
  fixed.x = generic.x = r.general.state.row(k0).transpose();
  fixed.P = generic.P = (r.general.sigma.row(k0).array().square() + 1e-6).matrix().asDiagonal();
  fixed_w.x = generic_w.x = r.two_axis.state.row(k0).transpose();
  fixed_w.P = generic_w.P = (r.two_axis.sigma.row(k0).array().square() + 1e-4).matrix().asDiagonal();
  const Eigen::VectorXd q = Eigen::VectorXd::Constant(gen::kStates, 1e-5);
  const Eigen::VectorXd rg = Eigen::VectorXd::Constant(gen::kMeasurements, 1e-4);
  const Eigen::VectorXd rw = Eigen::VectorXd::Constant(wf::kMeasurements, 1e-3);
  const Eigen::MatrixXd none(0, 0);
  const auto fg = [&](const Eigen::VectorXd& x, const Eigen::VectorXd&, Eigen::VectorXd& out) { f(x, out); };
  const auto hg = [&](const Eigen::VectorXd& x, const Eigen::VectorXd&, Eigen::VectorXd& out) { h(x, out); };
  const auto identity = [](const Eigen::VectorXd& x, const Eigen::VectorXd&, Eigen::VectorXd& out) { out = x; };
  const auto hwg = [&](const Eigen::VectorXd& x, const Eigen::VectorXd&, Eigen::VectorXd& out) { hw(x, out); };
  const auto ff = [&](const nt::GeneralState& x, nt::GeneralState& out) { f(x, out); };
  const auto hf = [&](const nt::GeneralState& x, nt::GeneralMeasurement& out) { h(x, out); };
  const auto hwf = [&](const nt::WheelForceState& x, nt::WheelForceMeasurement& out) { hw(x, out); };
  for (Eigen::Index k = k0 + 1; k < k0 + 41; ++k) {  // measurements of the run's later estimates, offset
    Eigen::VectorXd y(gen::kMeasurements), yw(wf::kMeasurements);
    h(Eigen::VectorXd(r.general.state.row(k).transpose()), y);
    y.array() += 0.01;
    hw(Eigen::VectorXd(r.two_axis.state.row(k).transpose()), yw);
    yw.array() += 0.1;
    generic.P.diagonal() += q;
    fixed.P.diagonal() += q;
    ASSERT_TRUE(generic.step(fg, none, hg, rg.asDiagonal(), y));
    ASSERT_TRUE(fixed.step(ff, hf, rg, y));
    generic_w.P.diagonal().array() += 1e-3;
    fixed_w.P.diagonal().array() += 1e-3;
    ASSERT_TRUE(generic_w.step(identity, none, hwg, rw.asDiagonal(), yw));
    ASSERT_TRUE(fixed_w.update(hwf, rw, yw));
    EXPECT_NEAR(fixed.nis, generic.nis, 1e-9 * (1.0 + generic.nis));
    EXPECT_NEAR(fixed_w.log_det_pyy, generic_w.log_det_pyy, 1e-9 * (1.0 + std::abs(generic_w.log_det_pyy)));
  }
  EXPECT_TRUE(same(fixed.x, generic.x)) << (fixed.x - generic.x).norm();
  EXPECT_TRUE(same(fixed.P, generic.P)) << (fixed.P - generic.P).norm();
  EXPECT_TRUE(same(fixed_w.x, generic_w.x)) << (fixed_w.x - generic_w.x).norm();
  EXPECT_TRUE(same(fixed_w.P, generic_w.P)) << (fixed_w.P - generic_w.P).norm();
  EXPECT_GT((fixed.x - Eigen::VectorXd(r.general.state.row(k0).transpose())).norm(), 1e-3);  // it moved
}

// The shape split of the bogie's perpendicular load: with the two bogie
// wheels on one contact angle and DP/W differing as the shape says (here
// DP = 0.5 s W + 0.02 W: DP/W independent of W), it recovers the loads
// across their links exactly, where Eq. 5.66 (equal DP/W) does not.
TEST(NetTraction, TheShapeSplitRecoversTheBogieWheelsLoadsAcrossTheirLinks) {
  const nt::RoverConstants rover;
  const auto& g = rover.geometry;
  nt::GeneralState x = nt::GeneralState::Zero();
  x(gen::kPitch) = 0.05;
  x(gen::kBogie) = -0.12;
  x(gen::kSlip + 1) = 0.1;
  x(gen::kSlip + 2) = 0.3;
  const double gamma = 0.08, a = gamma + x(gen::kPitch) + x(gen::kBogie);
  const Eigen::Vector2d W(48.0, 61.0);
  const Eigen::Vector2d dp(W(0) * (0.5 * 0.1 + 0.02), W(1) * (0.5 * 0.3 + 0.02));
  Eigen::Vector3d loads(40.0, 0.0, 0.0), across = Eigen::Vector3d::Zero();
  for (int j = 0; j < 2; ++j) {  // Eq. 5.58-5.59
    loads(1 + j) = W(j) * std::cos(a) + dp(j) * std::sin(a);
    across(1 + j) = -W(j) * std::sin(a) + dp(j) * std::cos(a);
  }
  const double lz = 0.5 * (g.bogie_to_wheel2.y() + g.bogie_to_wheel3.y());  // Eq. 5.64 solved for the moment
  x(gen::kMomentBogie) =
      (across(1) + across(2)) * lz - loads(1) * g.bogie_to_wheel2.x() - loads(2) * g.bogie_to_wheel3.x();
  const nt::DrawbarPullShape shape = [](double load, double slip) { return 0.5 * slip * load; };
  const Eigen::Vector3d proportional = nt::perpendicular_from_net_forces(rover, x, loads);
  const Eigen::Vector3d shaped =
      nt::perpendicular_from_net_forces(rover, x, loads, Eigen::Vector3d(0.0, gamma, gamma), shape);
  EXPECT_NEAR(shaped(1) + shaped(2), across(1) + across(2), 1e-9);
  EXPECT_NEAR(shaped(1), across(1), 1e-6);
  EXPECT_NEAR(shaped(2), across(2), 1e-6);
  EXPECT_GT(std::abs(proportional(1) - across(1)), 1.0);  // N: what Eq. 5.66 gets wrong here
  EXPECT_EQ(shaped(0), proportional(0));                  // wheel 1 (Eq. 5.65) is not split
  // No contact angle measured: Eq. 5.66.
  const Eigen::Vector3d unmeasured =
      nt::perpendicular_from_net_forces(rover, x, loads, Eigen::Vector3d(0.0, NAN, gamma), shape);
  EXPECT_EQ(unmeasured, proportional);
}

// `--bogie-split auto` (the default): the second pass is kept only when its
// drawbar pulls fit one order-2 surface about as well as the first pass's
// (RMS grown by less than 25 %). On the 200 s run it is kept and is closer to
// the true local model; on the 100 s run (a smaller region, a poorer pass-1
// shape) it is refused and would have been further from it.
TEST(NetTraction, AutoKeepsTheSecondPassOnlyWhereItsPointsStayConsistent) {
  for (const int seconds : {200, 100}) {
    const auto& r = rolling_result(seconds);
    const auto second = analysis::single_axis_second_pass(rolling_log(seconds), {}, {}, r, {});
    const double growth =
        analysis::single_axis_drawbar_pull_fit_rmse(second, {}) / analysis::single_axis_drawbar_pull_fit_rmse(r, {});
    const bool kept = growth < analysis::kSecondPassFitGrowthLimit;
    const auto one = analysis::rebuild_net_traction_model(rolling_log(seconds), r, r.single_axis, {}, 2);
    const auto two = analysis::rebuild_net_traction_model(rolling_log(seconds), second, second.single_axis, {}, 2);
    std::printf("%d s: fit RMS growth %.2f, DP vs truth Eq. 5.66 %.2f %%, shape %.2f %%\n", seconds, growth,
                one.drawbar_pull.comparison.rms_percent, two.drawbar_pull.comparison.rms_percent);
    EXPECT_EQ(kept, seconds == 200) << seconds << " s: growth " << growth;
    EXPECT_EQ(kept, two.drawbar_pull.comparison.rms_percent < one.drawbar_pull.comparison.rms_percent) << seconds;
    // What the analysis runs (choose_bogie_split) makes the same choice on the same evidence.
    estimation::NetTractionResult chosen = r;
    const analysis::BogieSplitChoice choice =
        analysis::choose_bogie_split(rolling_log(seconds), {}, {}, analysis::BogieSplit::automatic, {}, chosen);
    EXPECT_TRUE(choice.compared);
    EXPECT_EQ(choice.shape, kept) << seconds;
    EXPECT_NEAR(choice.second_pass_fit_rmse / choice.first_pass_fit_rmse, growth, 1e-9);
    estimation::NetTractionResult eq = r;
    EXPECT_FALSE(
        analysis::choose_bogie_split(rolling_log(seconds), {}, {}, analysis::BogieSplit::eq_5_66, {}, eq).shape);
  }
}

// A rover that drives is told from one that stands with a noisy velocimeter
// or a single spike: the forward speed averaged over a second.
TEST(NetTraction, ARoverDrivesWhenItsSpeedAveragedOverASecondExceeds2MmPerSecond) {
  std::vector<double> t, standing, spike, creeping;
  for (int k = 0; k < 500; ++k) {
    t.push_back(0.01 * k);
    standing.push_back(k % 2 == 0 ? 0.01 : -0.01);          // noise of 1 cm/s, mean zero
    spike.push_back(k == 250 ? 0.1 : 0.0);                  // one sample of 10 cm/s: 1 mm/s over that second
    creeping.push_back(k >= 200 && k < 320 ? 0.003 : 0.0);  // 3 mm/s for 1.2 s
  }
  const auto stream = [&](const std::vector<double>& v) {
    log::Stream s("velocimeter", t);
    s.add_channel("forward_speed", "m/s", v);
    return s;
  };
  EXPECT_FALSE(analysis::drives(stream(standing)));
  EXPECT_FALSE(analysis::drives(stream(spike)));
  EXPECT_TRUE(analysis::drives(stream(creeping)));
  EXPECT_FALSE(analysis::drives(stream(creeping), 0.004));
}

// Section 5.8 / Table 5.2: order-2 surfaces from the estimates against the
// true local model over the traversed region, in % of the quantity's range.
TEST(NetTraction, RebuiltSurfacesMatchTheTrueLocalModelAndGiveTheSoil) {
  const auto& r = rolling_result(200);
  const auto two = analysis::rebuild_net_traction_model(rolling_log(200), r, r.two_axis, {}, 2);
  const auto one = analysis::rebuild_net_traction_model(rolling_log(200), r, r.single_axis, {}, 2);
  ASSERT_TRUE(two.resistive_torque.has_truth && two.drawbar_pull.has_truth);
  EXPECT_GT(two.points, 1000u);
  EXPECT_GT(two.region.load_max - two.region.load_min, 20.0);  // N
  EXPECT_GT(two.region.slip_max - two.region.slip_min, 0.15);
  EXPECT_LT(two.resistive_torque.comparison.rms_percent, 2.5);
  EXPECT_LT(two.drawbar_pull.comparison.rms_percent, 2.5);
  EXPECT_LT(one.resistive_torque.comparison.rms_percent, 3.0);
  EXPECT_LT(one.drawbar_pull.comparison.rms_percent, 4.0);  // Eq. 5.66 alone: 3.25 %, the 3 % missed
  // The second pass (`--bogie-split shape`: the split from pass 1's DP(W, s)
  // shape) meets it on this 200 s run: 2.50 % (not on 100-150 s runs, where
  // it is worse than Eq. 5.66: docs/validation/net-traction.md).
  const auto second = analysis::single_axis_second_pass(rolling_log(200), {}, {}, r, {});
  const auto shaped = analysis::rebuild_net_traction_model(rolling_log(200), second, second.single_axis, {}, 2);
  std::printf(
      "single-axis DP surface vs the true local model: Eq. 5.66 %.2f %%, two passes %.2f %% (largest %.1f %%)\n",
      one.drawbar_pull.comparison.rms_percent, shaped.drawbar_pull.comparison.rms_percent,
      shaped.drawbar_pull.comparison.max_percent);
  EXPECT_LT(shaped.drawbar_pull.comparison.rms_percent, 3.0);
  EXPECT_LT(shaped.drawbar_pull.comparison.rms_percent, one.drawbar_pull.comparison.rms_percent - 0.4);
  EXPECT_LT(shaped.drawbar_pull.comparison.max_percent, one.drawbar_pull.comparison.max_percent);
  EXPECT_LT(shaped.resistive_torque.comparison.rms_percent, 3.0);
  // The true local model of order 2 is itself a close fit to the truth there.
  EXPECT_LT(two.drawbar_pull.truth.error.rmse, 0.05 * two.drawbar_pull.comparison.range);

  // Issue 12 item 5 on the same points: the soil fitted to them comes out
  // low (2.22) because this run's traction is the simulator's order-5
  // surrogate of Wong-Reece (seed 003 Appendix A), not Wong-Reece: fitted to
  // the surrogate's own exact values at the same loads and slips, Wong-Reece
  // gives the same strength. SoilFromTheEstimatesRecoversTheSimulatedStrength
  // holds the estimates themselves to the truth on a Wong-Reece run.
  const auto soil = io::load_soil(std::string(ROVERLAB_RESOURCES_DIR) + "/soils/ding_tyii.json");
  using P = terramechanics::Parameter;
  const auto s =
      analysis::identify_soil_from_points(two.estimated_points, soil, {}, {P::soil_strength, P::shear_modulus});
  ASSERT_TRUE(s.fit.converged && s.fit.covariance_ok);
  const simulation::rocker_bogie::TractionModel surrogate({}, rolling_run(200, simulation::TractionSource::polynomial),
                                                          true);
  std::vector<analysis::TractionPoint> exact = two.estimated_points;
  std::size_t unsupported = 0;
  for (auto& p : exact) {
    const auto t = surrogate.evaluate(p.load, p.slip, false, unsupported);
    p.drawbar_pull = t.drawbar_pull;
    p.resistive_torque = t.resistive_torque;
  }
  const auto e = analysis::identify_soil_from_points(exact, soil, {}, {P::soil_strength, P::shear_modulus});
  ASSERT_TRUE(e.fit.converged);
  std::printf("soil strength from the estimates %.3f +- %.3f (tau %.1f), from the surrogate's exact values %.3f\n",
              s.fit.parameters[0].value, s.fit.parameters[0].sigma, s.correlation_factor, e.fit.parameters[0].value);
  EXPECT_LT(e.fit.parameters[0].value, 2.35);  // the surrogate's own misfit: 2.5 is not what it encodes here
  EXPECT_NEAR(s.fit.parameters[0].value, e.fit.parameters[0].value, 2.0 * s.fit.parameters[0].sigma);
  EXPECT_LT(std::abs(s.fit.correlation[1]), 0.95);
  EXPECT_TRUE(s.confounded.empty());
  // With the sinkage exponent free as well, the region cannot tell the three apart.
  const auto three =
      analysis::identify_soil_from_points(two.estimated_points, soil, {}, {P::soil_strength, P::n, P::shear_modulus});
  EXPECT_FALSE(three.confounded.empty());
}

// Issue 12 item 5: on the validation run simulated with Wong-Reece traction
// (the model the identification fits), the soil fitted to the estimated
// steady-state points recovers the simulated strength (TYII x 2.5) and
// shear modulus within 2 sigma.
TEST(NetTraction, SoilFromTheEstimatesRecoversTheSimulatedStrength) {
  const auto& lg = rolling_log(200, simulation::TractionSource::wong_reece);
  const auto r = estimation::run_net_traction(lg, {}, {});
  const auto m = analysis::rebuild_net_traction_model(lg, r, r.two_axis, {}, 2);
  const auto soil = io::load_soil(std::string(ROVERLAB_RESOURCES_DIR) + "/soils/ding_tyii.json");
  using P = terramechanics::Parameter;
  const auto s =
      analysis::identify_soil_from_points(m.estimated_points, soil, {}, {P::soil_strength, P::shear_modulus});
  ASSERT_TRUE(s.fit.converged && s.fit.covariance_ok);
  const auto& strength = s.fit.parameters[0];
  const auto& k = s.fit.parameters[1];
  EXPECT_GT(strength.sigma, 0.0);
  std::printf("soil strength %.3f +- %.3f, K %.5f +- %.5f m (tau %.1f, reduced chi2 %.1f)\n", strength.value,
              strength.sigma, k.value, k.sigma, s.correlation_factor, s.reduced_chi2);
  EXPECT_LT(strength.sigma, 0.12);
  EXPECT_NEAR(strength.value, 2.5, 2.0 * strength.sigma);
  EXPECT_NEAR(k.value, soil.shear_modulus, 2.0 * k.sigma);
}

namespace {

// TYII 2.5 times stronger (cohesion, tan(friction angle), kc, kphi: what the
// simulator's soil-strength effect scales), so that the soil-strength effect
// can weaken it where the front wheel passes effect_start_x.
log::Log changing_soil_log(unsigned seed, double strength_after, double change_x, double seconds) {
  simulation::RockerBogieRun run;
  auto soil = io::load_soil(std::string(ROVERLAB_RESOURCES_DIR) + "/soils/ding_tyii.json");
  soil.cohesion *= 2.5;
  soil.friction_angle = std::atan(2.5 * std::tan(soil.friction_angle));
  soil.kc *= 2.5;
  soil.kphi *= 2.5;
  run.soil = soil;
  run.path = simulation::rolling_path();
  run.effects.soil_strength = strength_after;
  run.effects.effect_start_x = change_x;
  run.duration = seconds;
  run.seed = seed;
  return simulation::simulate_rocker_bogie({}, {}, run).log;
}

}  // namespace

// Issue 12 item 6, the hidden-effect test: the soil weakens by 25 % (2.5 ->
// 1.875 times TYII) where the front wheel passes X, drawn from a seed in
// 0.4-0.9 m of a 90 s run (about 1.6 m); the detector must place the change
// within 0.3 m of X, and a run with no change must report none.
TEST(NetTraction, ASoilChangeUnderTheRoverIsFoundWhereItHappened) {
  for (unsigned seed : {11u, 12u, 13u}) {
    std::mt19937 random(seed);
    const double x = std::uniform_real_distribution<double>(0.4, 0.9)(random);
    const log::Log lg = changing_soil_log(seed, 0.75, x, 90);
    const auto r = estimation::run_net_traction(lg, {}, {});
    // The dead-reckoned front wheel against the truth at the end (m).
    const auto truth_x = lg.stream("truth/wheels").interpolate("centre_x_1", {r.time.back()});
    EXPECT_NEAR(r.wheel_x(r.wheel_x.rows() - 1, 0), truth_x[0], 0.05) << seed;
    const auto m = analysis::rebuild_net_traction_model(lg, r, r.two_axis, {}, 2);
    ASSERT_EQ(m.changes.changes.size(), 1u) << seed;
    EXPECT_NEAR(m.changes.changes[0].x, x, 0.3) << seed;
    EXPECT_GT(m.changes.changes[0].statistic, analysis::ChangeDetectorOptions{}.threshold);
    // The front wheel reached X when the change point says.
    const auto front = lg.stream("truth/wheels").interpolate("centre_x_1", {m.changes.changes[0].front_wheel_time});
    EXPECT_NEAR(front[0], x, 0.3) << seed;
  }
  const log::Log same = changing_soil_log(14, 1.0, -1e9, 90);
  const auto r = estimation::run_net_traction(same, {}, {});
  const auto m = analysis::rebuild_net_traction_model(same, r, r.two_axis, {}, 2);
  EXPECT_TRUE(m.changes.changes.empty());
  EXPECT_LT(m.changes.largest_statistic, analysis::ChangeDetectorOptions{}.threshold);
  EXPECT_GT(m.changes.largest_statistic, 0.0);  // the scan ran
}

// The change detector's calibration (docs/validation/net-traction.md): the
// largest lambda and where, on runs without a change and with the soil
// 25 % and 15 % weaker past X, for several seeds and two durations. Run by
// hand with --gtest_also_run_disabled_tests.
TEST(NetTraction, DISABLED_ChangeDetectorCalibration) {
  for (double seconds : {90.0, 200.0}) {
    for (unsigned seed = 21; seed < 27; ++seed) {
      std::mt19937 random(seed);
      const double x = std::uniform_real_distribution<double>(0.4, 0.9)(random);
      std::printf("%.0f s seed %u, change at %.2f m:", seconds, seed, x);
      for (double strength : {1.0, 0.75, 0.85}) {
        const log::Log lg = changing_soil_log(seed, strength, strength == 1.0 ? -1e9 : x, seconds);
        const auto r = estimation::run_net_traction(lg, {}, {});
        const auto m = analysis::rebuild_net_traction_model(lg, r, r.two_axis, {}, 2);
        std::printf(" | strength %.2f: largest %.2f at %.2f m, %zu change(s)", strength, m.changes.largest_statistic,
                    m.changes.largest_at, m.changes.changes.size());
        if (strength == 1.0) {
          EXPECT_TRUE(m.changes.changes.empty()) << seconds << " s, seed " << seed;
        }
        if (strength == 0.75) {
          ASSERT_EQ(m.changes.changes.size(), 1u) << seconds << " s, seed " << seed;
          EXPECT_NEAR(m.changes.changes[0].x, x, 0.3) << seconds << " s, seed " << seed;
        }
      }
      std::printf("\n");
    }
  }
}

namespace {

// The log with spikes added to channels of the forces, imu and velocimeter
// streams: {stream, channel, size, count}, the count spread evenly over the log.
struct Spike {
  const char* stream;
  const char* channel;
  double size;
  int count;
};
log::Log with_spikes(const log::Log& lg, const std::vector<Spike>& spikes) {
  log::Log out;
  out.metadata = lg.metadata;
  for (const log::Stream& s : lg.streams()) {
    log::Stream copy(s.name(), s.time());
    for (const log::Channel& c : s.channels()) {
      std::vector<double> v = c.values;
      for (const Spike& k : spikes) {
        if (s.name() != k.stream || c.name != k.channel) continue;
        for (int i = 0; i < k.count; ++i) v[v.size() * static_cast<std::size_t>(2 * i + 1) / (2 * k.count)] += k.size;
      }
      copy.add_channel(c.name, c.unit, std::move(v), c.description);
    }
    out.add_stream(std::move(copy));
  }
  return out;
}

}  // namespace

// Issue 17 for the net-traction filters: 40 gross outliers (10 each on a
// link load, a perpendicular load, the forward accelerometer and the
// velocimeter) barely move the estimates with the NIS gate, and ruin some
// without it.
TEST(NetTraction, OutliersInForceOrImuChannelsAreGatedAway) {
  const log::Log& clean = rolling_log(100);
  const log::Log bad = with_spikes(clean, {{"forces", "load_2", 150.0, 10},
                                           {"forces", "perpendicular_1", -100.0, 10},
                                           {"imu", "specific_force_x", 80.0, 10},
                                           {"velocimeter", "forward_speed", 1.0, 10}});
  const auto& r0 = rolling_result(100);
  const auto r1 = estimation::run_net_traction(bad, {}, {});
  estimation::NetTractionOptions ungated;
  ungated.gate_probability = 1.0;
  const auto r2 = estimation::run_net_traction(bad, {}, ungated);
  std::printf("rejected on the clean log: %zu %zu %zu of %zu\n", r0.rejected_updates[0], r0.rejected_updates[1],
              r0.rejected_updates[2], r0.time.size());
  // Clean: the gate rarely fires; with the spikes (at the same 10 samples
  // in each channel) it rejects those updates.
  for (std::size_t f = 0; f < 3; ++f) EXPECT_LT(r0.rejected_updates[f], r0.time.size() / 100) << f;  // < 1 %
  EXPECT_GE(r1.rejected_updates[0], r0.rejected_updates[0] + 10);
  EXPECT_GE(r1.rejected_updates[1], r0.rejected_updates[1] + 10);
  const auto e0 = estimation::tracking_errors(clean, r0, r0.two_axis);
  const auto e1 = estimation::tracking_errors(bad, r1, r1.two_axis);
  const auto e2 = estimation::tracking_errors(bad, r2, r2.two_axis);
  double worst_gated = 0, worst_ungated = 0;  // largest relative RMS growth
  for (int i = 0; i < 3; ++i) {
    const std::pair<double, double> q[] = {{e1.normal_load(i), e0.normal_load(i)},
                                           {e1.drawbar_pull(i), e0.drawbar_pull(i)},
                                           {e1.resistive_torque(i), e0.resistive_torque(i)},
                                           {e1.slip(i), e0.slip(i)},
                                           {e1.contact_angle(i), e0.contact_angle(i)}};
    const std::pair<double, double> u[] = {{e2.normal_load(i), e0.normal_load(i)},
                                           {e2.drawbar_pull(i), e0.drawbar_pull(i)},
                                           {e2.resistive_torque(i), e0.resistive_torque(i)},
                                           {e2.slip(i), e0.slip(i)},
                                           {e2.contact_angle(i), e0.contact_angle(i)}};
    for (const auto& [now, before] : q) worst_gated = std::max(worst_gated, now / before - 1.0);
    for (const auto& [now, before] : u) worst_ungated = std::max(worst_ungated, now / before - 1.0);
  }
  std::printf("largest RMS growth: gated %.3f, ungated %.3f; rejected %zu %zu %zu\n", worst_gated, worst_ungated,
              r1.rejected_updates[0], r1.rejected_updates[1], r1.rejected_updates[2]);
  EXPECT_LT(worst_gated, 0.10);
  EXPECT_GT(worst_ungated, 0.5);
}

TEST(NetTraction, TooFewSteadyStatePointsAreRefused) {
  const auto& r = rolling_result(20);
  analysis::SteadyStateOptions o;
  o.window_seconds = 0.4;  // 2 averaged points per wheel
  EXPECT_THROW(analysis::rebuild_net_traction_model(rolling_log(20), r, r.two_axis, o, 2), DataError);
}

TEST(NetTraction, LogsLackingStreamsOrPerpendicularLoadsAreRefused) {
  log::Log without;
  for (const auto& s : rolling_log(20).streams()) {
    if (s.name() != "forces") without.add_stream(s);
  }
  EXPECT_EQ(estimation::net_traction_missing(without), "no forces stream");
  EXPECT_THROW(estimation::run_net_traction(without, {}, {}), DataError);
  log::Log single;
  for (const auto& s : rolling_log(20).streams()) {
    if (s.name() != "forces") {
      single.add_stream(s);
      continue;
    }
    log::Stream f("forces", s.time());
    for (int i = 1; i <= 3; ++i)
      f.add_channel("load_" + std::to_string(i), "N", s.channel("load_" + std::to_string(i)).values);
    single.add_stream(std::move(f));
  }
  EXPECT_FALSE(estimation::has_two_axis_force_sensors(single));
  estimation::NetTractionOptions o;
  o.force_sensors = estimation::ForceSensors::two_axis;
  EXPECT_THROW(estimation::run_net_traction(single, {}, o), DataError);
  // By default such a log runs Estimator 3 only, and its streams come from it.
  const auto r = estimation::run_net_traction(single, {}, {});
  EXPECT_EQ(r.force_sensors, estimation::ForceSensors::single_axis);
  EXPECT_TRUE(r.two_axis.empty());
  EXPECT_FALSE(r.single_axis.empty());
}

TEST(NetTraction, ClosedFormInertiaAndGravityEqualTheSimulators) {
  const nt::RoverConstants rover;
  namespace rb = simulation::rocker_bogie;
  for (const auto& [pitch, bogie] : {std::pair{0.0, 0.0}, std::pair{0.17, -0.06}, std::pair{-0.3, 0.2}}) {
    rb::Vec q = rb::Vec::Zero();
    q(2) = pitch;
    q(3) = bogie;
    const rb::Kinematics k = rb::kinematics(rover.geometry, rover.parameters, q);
    const rb::Mat H = rb::inertia(k, rover.parameters);
    const auto& p = rover.parameters;
    Eigen::Matrix<double, 1, rb::N> height = p.body_mass * k.J_body.row(1) + p.bogie_mass * k.J_bogie.row(1);
    for (const auto& J : k.J_wheel) height += p.wheel_mass * J.row(1);
    const nt::ConfigurationTerms t = nt::configuration_terms(rover, pitch, bogie);
    EXPECT_LT((t.inertia - H).cwiseAbs().maxCoeff(), 1e-12);
    EXPECT_LT((t.gravity - p.gravity * height.transpose()).cwiseAbs().maxCoeff(), 1e-10);
  }
}
