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

#include <Eigen/Dense>

#include "core/analysis/net_traction_surface.h"
#include "core/common/error.h"
#include "core/estimation/net_traction.h"
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
const log::Log& rolling_log() {
  static const log::Log lg = [] {
    simulation::RockerBogieRun run;
    run.soil = io::load_soil(std::string(ROVERLAB_RESOURCES_DIR) + "/soils/ding_tyii.json");
    run.path = simulation::rolling_path();
    run.effects.soil_strength = 2.5;
    run.duration = 100.0;
    return simulation::simulate_rocker_bogie({}, {}, run).log;
  }();
  return lg;
}

const estimation::NetTractionResult& rolling_result() {
  static const estimation::NetTractionResult r = estimation::run_net_traction(rolling_log(), {}, {});
  return r;
}

}  // namespace

TEST(NetTraction, EstimatesTrackTheTruth) {
  const auto& r = rolling_result();
  for (const auto* track : {&r.two_axis, &r.single_axis}) {
    const auto e = estimation::tracking_errors(rolling_log(), r, *track);
    ASSERT_TRUE(e.has_truth);
    std::printf("W %s\nDP %s\ntau %s\ns %s\ng %s\n", "", "", "", "", "");
    std::cout << e.normal_load.transpose() << "\n"
              << e.drawbar_pull.transpose() << "\n"
              << e.resistive_torque.transpose() << "\n"
              << e.slip.transpose() << "\n"
              << e.contact_angle.transpose() << "\n";
    const auto& tw = rolling_log().stream("truth/wheels");
    for (int i = 0; i < 3; ++i) {
      double bg = 0, bd = 0; int n = 0;
      for (Eigen::Index k = 250; k < track->state.rows(); ++k) {
        bg += track->state(k, i) - tw.channel("contact_angle_" + std::to_string(i + 1)).values[k];
        bd += track->state(k, 6 + i) - tw.channel("drawbar_pull_" + std::to_string(i + 1)).values[k];
        ++n;
      }
      std::printf("bias wheel %d: gamma %.4f rad DP %.3f N\n", i + 1, bg / n, bd / n);
    }
  }
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
  const Eigen::VectorXd sv = svd.singularValues();
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
  const auto& r = rolling_result();
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
  const auto& r = rolling_result();
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

TEST(NetTraction, RebuiltSurfacesMatchTheTrueLocalModel) {
  const auto& r = rolling_result();
  std::printf("filter %.3f s\n", r.filter_seconds);
  {
    const auto c0 = std::clock();
    auto again = estimation::run_net_traction(rolling_log(), {}, {});

    std::printf("cpu %.3f s (wall %.3f)\n", double(std::clock() - c0) / CLOCKS_PER_SEC, again.filter_seconds);
  }
  for (const auto* track : {&r.two_axis, &r.single_axis}) {
    for (int order : {0, 2, 3}) {
      const auto m = analysis::rebuild_net_traction_model(rolling_log(), r, *track, {}, order);
      std::printf("order %d/%d points %zu region W %.1f-%.1f s %.3f-%.3f cov %.2f: DP rms %.2f%% max %.2f%% range %.2f | tau rms %.2f%% max %.2f%% range %.3f\n",
                  order, m.drawbar_pull.estimate.surface.order(), m.points, m.region.load_min, m.region.load_max,
                  m.region.slip_min, m.region.slip_max, m.region.grid.coverage(), m.drawbar_pull.comparison.rms_percent,
                  m.drawbar_pull.comparison.max_percent, m.drawbar_pull.comparison.range,
                  m.resistive_torque.comparison.rms_percent, m.resistive_torque.comparison.max_percent,
                  m.resistive_torque.comparison.range);
    }
  }
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
