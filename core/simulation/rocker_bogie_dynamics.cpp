#include "core/simulation/rocker_bogie_dynamics.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <Eigen/Dense>

#include "core/common/error.h"
#include "core/terramechanics/slip_angle_model.h"

namespace roverlab::simulation::rocker_bogie {

namespace {

// Derivative of the clockwise rotation with respect to its angle.
Vec2 drotate(double a, const Vec2& v) {
  return {-std::sin(a) * v.x() + std::cos(a) * v.y(), -std::cos(a) * v.x() - std::sin(a) * v.y()};
}

void set_translation_base(Jac& J) {
  J.setZero();
  J(0, 0) = 1;
  J(1, 1) = 1;
}

// Solves H X = B in place for a small symmetric positive definite H by its
// Cholesky factor, in plain loops with one division per row.
template <int M, int K>
void cholesky_solve(const Eigen::Matrix<double, M, M>& H, Eigen::Matrix<double, M, K>& B) {
  double L[M][M];
  double inv[M];  // 1 / L(j, j)
  for (int j = 0; j < M; ++j) {
    double d = H(j, j);
    for (int k = 0; k < j; ++k) d -= L[j][k] * L[j][k];
    inv[j] = 1.0 / std::sqrt(d);
    for (int i = j + 1; i < M; ++i) {
      double v = H(i, j);
      for (int k = 0; k < j; ++k) v -= L[i][k] * L[j][k];
      L[i][j] = v * inv[j];
    }
  }
  for (int c = 0; c < K; ++c) {
    double y[M];
    for (int i = 0; i < M; ++i) {  // L y = b
      double v = B(i, c);
      for (int k = 0; k < i; ++k) v -= L[i][k] * y[k];
      y[i] = v * inv[i];
    }
    for (int i = M - 1; i >= 0; --i) {  // L^T x = y
      double v = y[i];
      for (int k = i + 1; k < M; ++k) v -= L[k][i] * y[k];
      y[i] = v * inv[i];
    }
    for (int i = 0; i < M; ++i) B(i, c) = y[i];
  }
}

}  // namespace

Vec2 rotate(double a, const Vec2& v) {
  return {std::cos(a) * v.x() + std::sin(a) * v.y(), -std::sin(a) * v.x() + std::cos(a) * v.y()};
}

Kinematics kinematics(const PlanarRockerBogieGeometry& g, const RockerBogieParameters& p, const Vec& q) {
  Kinematics k;
  const Vec2 r0(q(0), q(1));
  const double th = q(2), tb = q(2) + q(3);
  const Vec2 pivot = r0 + rotate(th, g.rocker_to_bogie);
  k.body = r0;
  k.bogie_com = pivot + rotate(tb, p.bogie_com);
  k.wheel[0] = r0 + rotate(th, g.rocker_to_wheel1);
  k.wheel[1] = pivot + rotate(tb, g.bogie_to_wheel2);
  k.wheel[2] = pivot + rotate(tb, g.bogie_to_wheel3);
  set_translation_base(k.J_body);
  set_translation_base(k.J_bogie);
  k.J_bogie.col(2) = drotate(th, g.rocker_to_bogie) + drotate(tb, p.bogie_com);
  k.J_bogie.col(3) = drotate(tb, p.bogie_com);
  set_translation_base(k.J_wheel[0]);
  k.J_wheel[0].col(2) = drotate(th, g.rocker_to_wheel1);
  for (int i = 1; i < 3; ++i) {
    const Vec2& l = i == 1 ? g.bogie_to_wheel2 : g.bogie_to_wheel3;
    set_translation_base(k.J_wheel[i]);
    k.J_wheel[i].col(2) = drotate(th, g.rocker_to_bogie) + drotate(tb, l);
    k.J_wheel[i].col(3) = drotate(tb, l);
  }
  k.W_body.setZero();
  k.W_body(2) = 1;
  k.W_bogie = k.W_body;
  k.W_bogie(3) = 1;
  k.W_wheel[0] = k.W_body;
  k.W_wheel[0](4) = 1;
  for (int i = 1; i < 3; ++i) {
    k.W_wheel[i] = k.W_bogie;
    k.W_wheel[i](4 + i) = 1;
  }
  return k;
}

// Eq. 4.29, with the drivetrain's reflected inertia on each wheel joint.
// The translation Jacobians move only x0, z0, pitch and bogie (their wheel
// columns are zero): their products fill H's top-left 4x4 alone.
Mat inertia(const Kinematics& k, const RockerBogieParameters& p) {
  using Jac4 = Eigen::Matrix<double, 2, 4>;
  const auto translation = [](double mass, const Jac& J) {
    const Jac4 J4 = J.leftCols<4>();
    return Eigen::Matrix4d(mass * J4.transpose() * J4);
  };
  Mat H = p.body_inertia * k.W_body.transpose() * k.W_body + p.bogie_inertia * k.W_bogie.transpose() * k.W_bogie;
  Eigen::Matrix4d T = translation(p.body_mass, k.J_body) + translation(p.bogie_mass, k.J_bogie);
  for (int i = 0; i < 3; ++i) {
    T += translation(p.wheel_mass, k.J_wheel[i]);
    H += p.wheel_inertia * k.W_wheel[i].transpose() * k.W_wheel[i];
    H(4 + i, 4 + i) += p.wheel_gear_inertia - p.wheel_inertia;
  }
  H.topLeftCorner<4, 4>() += T;
  return H;
}

// The Jacobians' rates in closed form: d/dt drotate(a, v) = -a' rotate(a, v)
// (the second derivative of the rotation is minus itself). They replace
// central differences of the kinematics at q +- h qd, two of the three
// kinematics (and their sines and cosines) per evaluation (issue 34, N8).
JacobianRates jacobian_rates(const PlanarRockerBogieGeometry& g, const Kinematics& k, const Vec& q, const Vec& qd) {
  const double th_dot = qd(2), tb_dot = qd(2) + qd(3);
  const Vec2 to_pivot = rotate(q(2), g.rocker_to_bogie);
  const Vec2 pivot = k.body + to_pivot;
  JacobianRates r;
  r.bogie.setZero();
  r.bogie.col(2) = -th_dot * to_pivot - tb_dot * (k.bogie_com - pivot);
  r.bogie.col(3) = -tb_dot * (k.bogie_com - pivot);
  r.wheel[0].setZero();
  r.wheel[0].col(2) = -th_dot * (k.wheel[0] - k.body);
  for (int i = 1; i < 3; ++i) {
    r.wheel[i].setZero();
    r.wheel[i].col(2) = -th_dot * to_pivot - tb_dot * (k.wheel[i] - pivot);
    r.wheel[i].col(3) = -tb_dot * (k.wheel[i] - pivot);
  }
  return r;
}

// Hdot qd of Eq. 4.49 from the velocity Jacobians' rates along qd:
// sum m (Jdot^T J qd + J^T Jdot qd). Equal to differencing Eq. 4.29's H,
// without its two 7x7 builds.
Vec inertia_rate_times(const Kinematics& k, const JacobianRates& rates, const RockerBogieParameters& p, const Vec& qd) {
  Vec out = Vec::Zero();
  const auto add = [&](double mass, const Jac& J, const Jac& Jd) {
    out += mass * (Jd.transpose() * (J * qd) + J.transpose() * (Jd * qd));
  };
  add(p.bogie_mass, k.J_bogie, rates.bogie);
  for (int i = 0; i < 3; ++i) add(p.wheel_mass, k.J_wheel[i], rates.wheel[i]);
  return out;
}

TractionModel::TractionModel(const PlanarRockerBogieGeometry& g, const RockerBogieRun& run, bool with_effects)
    : soil_(&run.soil), source_(run.traction) {
  const RockerBogieEffects& fx = run.effects;
  wheel_ = {g.wheel_radius * (with_effects ? fx.wheel_radius_scale : 1.0), g.wheel_width, 0, 0.0};
  if (with_effects) {
    options_.extensions.soil_strength = fx.soil_strength;
    options_.extensions.slip_sinkage_n1 = fx.slip_sinkage_n1;
    slip_angle_ = fx.slip_angle_deg * M_PI / 180.0;
    if (fx.grouser_height > 0) {
      wheel_.grouser_count = 24;
      wheel_.grouser_height = fx.grouser_height;
      options_.extensions.grousers = true;
    }
  }
  if (source_ == TractionSource::polynomial) fit_surrogate();
}

// A wheel at a slip angle loses drawbar pull and resistive torque to the
// lateral shear (Ishigami et al. 2007, Eq. 5-7, with one shared Mohr-Coulomb
// strength); its lateral force has no axis in this planar side.
terramechanics::Traction TractionModel::wheel_soil(double W, double s) const {
  if (slip_angle_ == 0.0) return terramechanics::evaluate(*soil_, wheel_, W, s, options_);
  return terramechanics::evaluate_slip_angle(*soil_, wheel_, W, s, slip_angle_, options_);
}

// Seed 003 Appendix A: order-5 surfaces over 1..150 N and slips -1..1.
void TractionModel::fit_surrogate() {
  std::vector<terramechanics::SurfaceSample> dp, tau, sink, resistance;
  for (int i = 0; i < 40; ++i) {
    for (int k = 0; k < 41; ++k) {
      const double W = 1.0 + 149.0 * i / 39.0, s = -1.0 + 2.0 * k / 40.0;
      const auto t = wheel_soil(W, s);
      if (!t.ok()) continue;
      dp.push_back({W, s, t.drawbar_pull});
      tau.push_back({W, s, t.resistive_torque});
      sink.push_back({W, s, t.sinkage});
      resistance.push_back({W, s, t.motion_resistance});
    }
  }
  if (dp.size() < 50) throw DataError("soil " + soil_->name + " cannot carry the rover's wheel loads");
  dp_ = terramechanics::fit_surface(dp, 5);
  tau_ = terramechanics::fit_surface(tau, 5);
  sinkage_ = terramechanics::fit_surface(sink, 5);
  resistance_ = terramechanics::fit_surface(resistance, 5);
}

// The load a wheel carries grows with its entry angle up to 90 deg (Eq.
// 2.24), so the loads carried at a slip are an interval from 0: bisection
// over whole newtons. A skid's sinkage is that of the mirrored slip.
double TractionModel::largest_carried_load(double limit) const {
  const auto carries = [&](double W) {
    for (double s : {0.0, 0.5, 1.0}) {
      if (!wheel_soil(W, s).ok()) return false;
    }
    return true;
  };
  double lo = 0.0, hi = std::floor(limit) + 1.0;  // carries lo (nothing), not hi
  if (carries(hi - 1.0)) return hi - 1.0;
  while (hi - lo > 1.0) {
    const double mid = std::floor(0.5 * (lo + hi));
    (mid >= 1.0 && carries(mid) ? lo : hi) = mid;
  }
  return lo;
}

WheelTraction TractionModel::evaluate(double W, double s, bool with_sinkage, std::size_t& unsupported,
                                      bool with_resistance) const {
  WheelTraction out;
  if (!(W > 0.0)) return out;
  if (source_ == TractionSource::polynomial) {
    W = std::min(W, 150.0);  // the surrogate's fitted range
    out.drawbar_pull = dp_(W, s);
    out.resistive_torque = tau_(W, s);
    if (with_resistance) out.resistance = std::max(0.0, resistance_(W, s));
    if (with_sinkage) out.sinkage = sinkage_(W, s);
    return out;
  }
  const auto t = wheel_soil(W, s);
  if (!t.ok()) {
    ++unsupported;
    out.sinkage = NAN;
    return out;
  }
  out.drawbar_pull = t.drawbar_pull;
  out.resistive_torque = t.resistive_torque;
  out.sinkage = t.sinkage;
  out.resistance = t.motion_resistance;
  return out;
}

Dynamics::Dynamics(const PlanarRockerBogieGeometry& g, const RockerBogieParameters& p, const RockerBogieRun& run)
    : g_(g), p_(p), run_(run), nominal_(g, run, false), changed_(g, run, true) {
  // Each wheel must be able to carry half this side's weight at any slip with
  // its entry angle below 90 deg (Eq. 2.24): beyond, the wheel would sink past
  // its axle, where the wheel-soil model has no answer (and its polynomial
  // surrogate extrapolates to sinkages over the radius: issue 34, N10).
  const double half = 0.5 * (p.body_mass + p.bogie_mass + 3 * p.wheel_mass) * p.gravity;
  for (const TractionModel* m : {&nominal_, &changed_}) {
    if (!run.refuse_unsupported_soil) break;
    const double carried = m->largest_carried_load(std::ceil(half));
    if (carried >= half) continue;
    char effects[96] = "";
    if (m == &changed_) {
      std::snprintf(effects, sizeof effects, " at soil strength %g, slip-sinkage n1 %g", run.effects.soil_strength,
                    run.effects.slip_sinkage_n1);
    }
    char text[320];
    std::snprintf(text, sizeof text,
                  "soil %s%s cannot carry the rover: at full slip a wheel sinks past its axle under %.0f N, and a "
                  "wheel may carry half this side's weight, %.0f N",
                  run.soil.name.c_str(), effects, carried + 1.0, half);
    throw DataError(text);
  }
}

void Dynamics::hold(const Eigen::Vector3d& torque, const Eigen::Vector3d& normal) {
  torque_ = torque;
  normal_ = normal;
}

// The share of the changed model at a wheel centre x: the effects begin at
// effect_start_x over a transition of kEffectTransition (a soil boundary is
// not a step, and a step would make the simulation's response to the
// effects' sizes and start jump with the integrator's steps).
constexpr double kEffectTransition = 0.01;  // m
double Dynamics::changed_share(double x) const {
  return std::clamp((x - run_.effects.effect_start_x) / kEffectTransition + 0.5, 0.0, 1.0);
}

WheelTraction Dynamics::traction_at(double w, double W, double s, bool with_sinkage, bool with_resistance) {
  if (w <= 0.0 || w >= 1.0)
    return (w >= 1.0 ? changed_ : nominal_).evaluate(W, s, with_sinkage, unsupported_, with_resistance);
  const WheelTraction a = nominal_.evaluate(W, s, with_sinkage, unsupported_, with_resistance);
  const WheelTraction b = changed_.evaluate(W, s, with_sinkage, unsupported_, with_resistance);
  return {(1 - w) * a.drawbar_pull + w * b.drawbar_pull, (1 - w) * a.resistive_torque + w * b.resistive_torque,
          (1 - w) * a.sinkage + w * b.sinkage, (1 - w) * a.resistance + w * b.resistance};
}

// Eq. 4.49-4.50: [H Psi_q^T; Psi_q 0] [qdd; -lambda] = [tau_a - Hdot qd; Baumgarte right-hand side].
void Dynamics::accelerations(const Vec& q, const Vec& qd, Vec& qdd, DynamicsReport* report) {
  const Kinematics k = kinematics(g_, p_, q);
  const Mat H = inertia(k, p_);
  const JacobianRates rates = jacobian_rates(g_, k, q, qd);
  const Vec Hdot_qd = inertia_rate_times(k, rates, p_, qd);
  Vec tau_a = Vec::Zero();
  // Gravity: -dV/dPhi (Eq. 4.37).
  tau_a -= p_.gravity * (p_.body_mass * k.J_body.row(1) + p_.bogie_mass * k.J_bogie.row(1)).transpose();
  Constraints c;
  for (int i = 0; i < 3; ++i) wheel(i, k, rates, qd, tau_a, c, report);
  const Eigen::Vector3d b2 = -c.Psidot_qd - 2 * p_.baumgarte_alpha * (c.Psi_q * qd) -
                             p_.baumgarte_beta * p_.baumgarte_beta * c.Psi;  // Eq. 4.17
  // [H -Psi_q^T; Psi_q 0] [qdd; lambda] = [tau_a - Hdot qd; b2], eliminated
  // in the structure of Eq. 4.29 and 4.33 (a 10x10 LU was a quarter of a
  // run's time; issue 34, N8): H = [A B; B^T D] with D diagonal (a wheel's
  // rotation couples only to pitch and bogie), Psi_q = [P 0] (the path holds
  // wheel centres, not their turning). The wheels' accelerations first, then
  // the reduced [A - B D^-1 B^T, -P^T; P 0] by its Schur complement; A - B
  // D^-1 B^T is positive definite as H is, P of full rank while the wheels
  // touch the path.
  const Vec rhs = tau_a - Hdot_qd;
  const Eigen::Matrix<double, 4, 3> B = H.topRightCorner<4, 3>();
  const Eigen::Vector3d d_inv = H.bottomRightCorner<3, 3>().diagonal().cwiseInverse();
  const Eigen::Matrix<double, 4, 3> BDi = B * d_inv.asDiagonal();
  const Eigen::Matrix4d reduced = H.topLeftCorner<4, 4>() - BDi * B.transpose();
  const Eigen::Matrix<double, 3, 4> P = c.Psi_q.leftCols<4>();
  Eigen::Matrix4d x;  // reduced^-1 [P^T, reduced right-hand side]
  x.leftCols<3>() = P.transpose();
  x.col(3) = rhs.head<4>() - BDi * rhs.tail<3>();
  cholesky_solve(reduced, x);
  const Eigen::Matrix3d S = P * x.leftCols<3>();
  Eigen::Vector3d lambda = b2 - P * x.col(3);
  cholesky_solve(S, lambda);
  const Eigen::Vector4d a = x.col(3) + x.leftCols<3>() * lambda;
  qdd.head<4>() = a;
  qdd.tail<3>() = d_inv.cwiseProduct(rhs.tail<3>() - B.transpose() * a);
  if (report) {
    report->lambda = lambda;
    report->qdd = qdd;
  }
}

void Dynamics::wheel(int i, const Kinematics& k, const JacobianRates& rates, const Vec& qd, Vec& tau_a,
                     Constraints& con, DynamicsReport* report) {
  tau_a -= p_.gravity * p_.wheel_mass * k.J_wheel[i].row(1).transpose();
  const Vec2 c = k.wheel[i];
  const Vec2 v = k.J_wheel[i] * qd;
  const Vec2 a = rates.wheel[i] * qd;  // Jdot qdot
  const double z1 = run_.path.dz(c.x()), z2 = run_.path.ddz(c.x());
  con.Psi(i) = c.y() - run_.path.z(c.x());  // Eq. 4.33
  con.Psi_q.row(i) = k.J_wheel[i].row(1) - z1 * k.J_wheel[i].row(0);
  con.Psidot_qd(i) = a.y() - z2 * v.x() * v.x() - z1 * a.x();
  // Traction at the wheel (Eq. 4.40-4.47): contact angle gamma = atan(z1) from the path's slope.
  const double secant = std::sqrt(1.0 + z1 * z1);  // 1 / cos(gamma)
  const Vec2 t(1.0 / secant, z1 / secant);         // (cos gamma, sin gamma)
  const double v_t = v.dot(t);
  const double omega = k.W_wheel[i] * qd;  // absolute wheel rate, clockwise = forward rolling
  // Slip (Eq. 2.23) or skid (Eq. 2.26) in the wheel's sense of rotation
  // (a wheel turning backwards sees the mirror image of the forward
  // traction). The steady-state traction of the terramechanics model
  // needs relative motion: it fades in over the first few mm/s of rim or
  // centre speed (tanh), so that a wheel at rest is not turned backwards
  // by its own resistive torque and the forces stay smooth through
  // standstill; a rover sliding back with its wheels still sees full slip.
  const double share = changed_share(c.x());
  const double radius = (1 - share) * nominal_.radius() + share * changed_.radius();
  const double roll_signed = omega * radius;
  const double dir = roll_signed < 0.0 ? -1.0 : 1.0;
  const double fade = std::tanh(std::max(std::abs(roll_signed), std::abs(v_t)) / 0.004);
  const double roll = dir * roll_signed, vt = dir * v_t;
  const double den = std::max({std::abs(roll), std::abs(vt), 1e-6});
  const double s = std::clamp((roll - vt) / den, -1.0, 1.0);
  const double W = normal_(i) > 0 ? normal_(i) * secant : 0.0;  // Eq. 4.38, held over the step
  // Sliding against the rolling (below): the compaction resistance is needed.
  const double against = std::tanh(std::max(0.0, -vt) / 0.004);
  const WheelTraction traction = traction_at(share, W, s, report != nullptr, against > 0.0);
  // A net resistance (DP < 0: compaction outweighs the shear thrust) opposes
  // the centre's motion along the path and vanishes with it: it can hold a
  // spinning wheel in place but never push the rover backwards (issue 34,
  // N10: a weak soil drove the rover back at -96 m/s).
  double dp = traction.drawbar_pull >= 0.0 ? traction.drawbar_pull * (dir * fade)
                                           : traction.drawbar_pull * std::tanh(v_t / 0.004);
  // A centre moving against the wheel's rolling (sliding down a slope, slip
  // beyond 1): the shear thrust H = DP + R still follows the rim, and the
  // compaction resistance R (Eq. 2.21's sigma sin(theta) term) now opposes
  // the slide too, so the soil holds with H + R rather than H - R (issue 34,
  // N10: on 11 deg at soil strength 0.5 the rover slid down at 8 m/s).
  const double thrust = std::max(0.0, traction.drawbar_pull + traction.resistance);
  dp += dir * against * 2.0 * (traction.drawbar_pull >= 0.0 ? traction.resistance : thrust);
  const double tr = traction.resistive_torque * (dir * fade);
  tau_a += k.J_wheel[i].transpose() * (dp * t);               // Eq. 4.43
  tau_a -= k.W_wheel[i].transpose() * tr;                     // Eq. 4.42: resists the wheel's rotation
  tau_a(4 + i) += torque_(i) - p_.wheel_damping * qd(4 + i);  // Eq. 4.46
  if (report) {
    report->slip(i) = s;
    report->dp(i) = dp;
    report->tau(i) = tr;
    report->gamma(i) = std::atan(z1);
    report->rate(i) = omega;
    report->sinkage(i) = traction.sinkage;
  }
}

void split_state(const State& x, Vec& q, Vec& qd) {
  for (int i = 0; i < N; ++i) {
    qd(i) = x[static_cast<std::size_t>(i)];
    q(i) = x[N + static_cast<std::size_t>(i)];
  }
}

void OdeSystem::operator()(const State& x, State& dx, double /*t*/) const {
  Vec q, qd, qdd;
  split_state(x, q, qd);
  dynamics->accelerations(q, qd, qdd, nullptr);
  for (int i = 0; i < N; ++i) {
    dx[static_cast<std::size_t>(i)] = qdd(i);
    dx[N + static_cast<std::size_t>(i)] = qd(i);
  }
}

}  // namespace roverlab::simulation::rocker_bogie
