#include "core/simulation/rocker_bogie.h"

#include <boost/numeric/odeint.hpp>

#include <array>
#include <random>
#include <cmath>
#include <vector>

#include <Eigen/Dense>

#include "core/common/error.h"
#include "core/terramechanics/traction_surface.h"

namespace roverlab::simulation {

namespace {

constexpr int N = 7;  // x0, z0, pitch, bogie, wheel 1..3
using Vec = Eigen::Matrix<double, N, 1>;
using Mat = Eigen::Matrix<double, N, N>;
using Jac = Eigen::Matrix<double, 2, N>;
using Vec2 = Eigen::Vector2d;

// Clockwise rotation in the x-z plane and its derivative.
Vec2 rot(double a, const Vec2& v) { return {std::cos(a) * v.x() + std::sin(a) * v.y(), -std::sin(a) * v.x() + std::cos(a) * v.y()}; }
Vec2 drot(double a, const Vec2& v) { return {-std::sin(a) * v.x() + std::cos(a) * v.y(), -std::cos(a) * v.x() - std::sin(a) * v.y()}; }

struct Kinematics {
  Vec2 body, bogie_com, wheel[3];
  Jac J_body, J_bogie, J_wheel[3];
  Eigen::Matrix<double, 1, N> W_body, W_bogie, W_wheel[3];  // angular-velocity Jacobians
};

Kinematics kinematics(const PlanarRockerBogieGeometry& g, const RockerBogieParameters& p, const Vec& q) {
  Kinematics k;
  const Vec2 r0(q(0), q(1));
  const double th = q(2), tb = q(2) + q(3);
  const Vec2 pivot = r0 + rot(th, g.rocker_to_bogie);
  k.body = r0;
  k.bogie_com = pivot + rot(tb, p.bogie_com);
  k.wheel[0] = r0 + rot(th, g.rocker_to_wheel1);
  k.wheel[1] = pivot + rot(tb, g.bogie_to_wheel2);
  k.wheel[2] = pivot + rot(tb, g.bogie_to_wheel3);
  auto base = [](Jac& J) {
    J.setZero();
    J(0, 0) = 1;
    J(1, 1) = 1;
  };
  base(k.J_body);
  base(k.J_bogie);
  k.J_bogie.col(2) = drot(th, g.rocker_to_bogie) + drot(tb, p.bogie_com);
  k.J_bogie.col(3) = drot(tb, p.bogie_com);
  base(k.J_wheel[0]);
  k.J_wheel[0].col(2) = drot(th, g.rocker_to_wheel1);
  for (int i = 1; i < 3; ++i) {
    const Vec2& l = i == 1 ? g.bogie_to_wheel2 : g.bogie_to_wheel3;
    base(k.J_wheel[i]);
    k.J_wheel[i].col(2) = drot(th, g.rocker_to_bogie) + drot(tb, l);
    k.J_wheel[i].col(3) = drot(tb, l);
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
Mat inertia(const Kinematics& k, const RockerBogieParameters& p) {
  Mat H = p.body_mass * k.J_body.transpose() * k.J_body + p.body_inertia * k.W_body.transpose() * k.W_body;
  H += p.bogie_mass * k.J_bogie.transpose() * k.J_bogie + p.bogie_inertia * k.W_bogie.transpose() * k.W_bogie;
  for (int i = 0; i < 3; ++i) {
    H += p.wheel_mass * k.J_wheel[i].transpose() * k.J_wheel[i] + p.wheel_inertia * k.W_wheel[i].transpose() * k.W_wheel[i];
    H(4 + i, 4 + i) += p.wheel_gear_inertia - p.wheel_inertia;
  }
  return H;
}

}  // namespace

void set_effect(RockerBogieEffects& e, const std::string& name, double v) {
  if (!std::isfinite(v)) throw DataError("effect " + name + ": not a number");
  if (name == "soil-strength") {
    if (!(v > 0.1 && v < 10)) throw DataError("effect soil-strength must be 0.1..10");
    e.soil_strength = v;
  } else if (name == "slip-sinkage") {
    if (!(v >= 0 && v <= 2)) throw DataError("effect slip-sinkage must be 0..2");
    e.slip_sinkage_n1 = v;
  } else if (name == "grousers") {
    if (!(v >= 0 && v <= 0.05)) throw DataError("effect grousers (height, m) must be 0..0.05");
    e.grouser_height = v;
  } else if (name == "wheel-radius-scale") {
    if (!(v > 0.5 && v < 2)) throw DataError("effect wheel-radius-scale must be 0.5..2");
    e.wheel_radius_scale = v;
  } else if (name == "effect-start-x") {
    e.effect_start_x = v;
  } else if (name == "gyro-bias") {
    e.gyro_bias = v;
  } else if (name == "accel-bias") {
    e.accel_bias = v;
  } else if (name == "force-offset") {
    e.force_offset = v;
  } else if (name == "force-scale") {
    if (!(v > 0)) throw DataError("effect force-scale must be positive");
    e.force_scale = v;
  } else if (name == "encoder-dropout") {
    e.encoder_dropout_start = v;
  } else if (name == "imu-time-offset") {
    e.imu_time_offset = v;
  } else {
    throw DataError("unknown effect '" + name + "' (soil-strength, slip-sinkage, grousers, wheel-radius-scale, "
                    "effect-start-x, gyro-bias, accel-bias, force-offset, force-scale, encoder-dropout, imu-time-offset)");
  }
}

WheelCentrePath rolling_path() {
  WheelCentrePath p;
  p.name = "rolling (seed 003 Eq. 4.51)";
  const double k = M_PI / 2;
  p.z = [k](double x) { return 0.12 * std::cos(k * x - 1.6) + 0.01 * x; };
  p.dz = [k](double x) { return -0.12 * k * std::sin(k * x - 1.6) + 0.01; };
  p.ddz = [k](double x) { return -0.12 * k * k * std::cos(k * x - 1.6); };
  return p;
}

WheelCentrePath slope_path(double degrees) {
  WheelCentrePath p;
  p.name = "slope " + std::to_string(degrees) + " deg";
  const double k = std::tan(degrees * M_PI / 180.0);
  p.z = [k](double x) { return k * x; };
  p.dz = [k](double) { return k; };
  p.ddz = [](double) { return 0.0; };
  return p;
}

WheelCentrePath bump_path(double height, double x0, double length) {
  WheelCentrePath p;
  p.name = "bump " + std::to_string(height) + " m at x = " + std::to_string(x0) + " m";
  const double w = 2.0 * M_PI / length;
  auto inside = [x0, length](double x) { return x >= x0 && x <= x0 + length; };
  p.z = [=](double x) { return inside(x) ? 0.5 * height * (1.0 - std::cos(w * (x - x0))) : 0.0; };
  p.dz = [=](double x) { return inside(x) ? 0.5 * height * w * std::sin(w * (x - x0)) : 0.0; };
  p.ddz = [=](double x) { return inside(x) ? 0.5 * height * w * w * std::cos(w * (x - x0)) : 0.0; };
  return p;
}

WheelCentrePath flat_path(double h) {
  WheelCentrePath p;
  p.name = "flat";
  p.z = [h](double) { return h; };
  p.dz = [](double) { return 0.0; };
  p.ddz = [](double) { return 0.0; };
  return p;
}

RockerBogieResult simulate_rocker_bogie(const PlanarRockerBogieGeometry& g, const RockerBogieParameters& p,
                                        const RockerBogieRun& run) {
  const RockerBogieEffects& fx = run.effects;
  // Traction before and after the effects' start: Wong-Reece, or its order-5
  // polynomial surrogate (seed 003 Appendix A) fitted once for each.
  struct TractionModel {
    terramechanics::Wheel wheel;
    terramechanics::ModelOptions options;
    terramechanics::PolynomialSurface dp, tau, sinkage;
  };
  auto make_model = [&](bool with_effects) {
    TractionModel m;
    m.wheel = {g.wheel_radius * (with_effects ? fx.wheel_radius_scale : 1.0), g.wheel_width, 0, 0.0};
    if (with_effects) {
      m.options.extensions.soil_strength = fx.soil_strength;
      m.options.extensions.slip_sinkage_n1 = fx.slip_sinkage_n1;
      if (fx.grouser_height > 0) {
        m.wheel.grouser_count = 24;
        m.wheel.grouser_height = fx.grouser_height;
        m.options.extensions.grousers = true;
      }
    }
    if (run.traction == TractionSource::polynomial) {
      std::vector<terramechanics::SurfaceSample> dp, tau, sink;
      for (int i = 0; i < 40; ++i) {
        for (int k = 0; k < 41; ++k) {
          const double W = 1.0 + 149.0 * i / 39.0, s = -1.0 + 2.0 * k / 40.0;
          const auto t = terramechanics::evaluate(run.soil, m.wheel, W, s, m.options);
          if (!t.ok()) continue;
          dp.push_back({W, s, t.drawbar_pull});
          tau.push_back({W, s, t.resistive_torque});
          sink.push_back({W, s, t.sinkage});
        }
      }
      if (dp.size() < 50) throw DataError("soil " + run.soil.name + " cannot carry the rover's wheel loads");
      m.dp = terramechanics::fit_surface(dp, 5);
      m.tau = terramechanics::fit_surface(tau, 5);
      m.sinkage = terramechanics::fit_surface(sink, 5);
    }
    return m;
  };
  const TractionModel nominal = make_model(false), changed = make_model(true);
  RockerBogieResult result;
  auto traction = [&](const TractionModel& m, double W, double s, double& dp, double& tau, double* sinkage) {
    if (!(W > 0.0)) {
      dp = tau = 0.0;
      if (sinkage) *sinkage = 0.0;
      return;
    }
    if (run.traction == TractionSource::polynomial) {
      W = std::min(W, 150.0);  // the surrogate's fitted range
      dp = m.dp(W, s);
      tau = m.tau(W, s);
      if (sinkage) *sinkage = m.sinkage(W, s);
      return;
    }
    const auto t = terramechanics::evaluate(run.soil, m.wheel, W, s, m.options);
    if (!t.ok()) {
      ++result.unsupported;
      dp = tau = 0.0;
      if (sinkage) *sinkage = NAN;
      return;
    }
    dp = t.drawbar_pull;
    tau = t.resistive_torque;
    if (sinkage) *sinkage = t.sinkage;
  };

  // Place the rover on the path: wheel 1 at start_x, all three wheel centres on it.
  Vec q = Vec::Zero();
  q(0) = run.start_x - g.rocker_to_wheel1.x();
  q(1) = run.path.z(run.start_x) - g.rocker_to_wheel1.y();
  for (int it = 0; it < 50; ++it) {
    auto residual = [&](const Vec& x) {
      const Kinematics k = kinematics(g, p, x);
      Eigen::Vector4d r;
      for (int i = 0; i < 3; ++i) r(i) = k.wheel[i].y() - run.path.z(k.wheel[i].x());
      r(3) = k.wheel[0].x() - run.start_x;
      return r;
    };
    const Eigen::Vector4d r = residual(q);
    if (r.norm() < 1e-12) break;
    Eigen::Matrix4d J;
    for (int c = 0; c < 4; ++c) {
      Vec d = Vec::Zero();
      d(c) = 1e-7;
      J.col(c) = (residual(q + d) - residual(q - d)) / 2e-7;
    }
    q.head<4>() -= J.fullPivLu().solve(r);
  }

  const double dt = 1.0 / p.control_rate;
  Eigen::Vector3d torque = Eigen::Vector3d::Zero(), normal = Eigen::Vector3d::Constant(-1.0), integral = Eigen::Vector3d::Zero();
  // Derivative of the state [qdot; q] (Eq. 4.49-4.50).
  struct Out {
    Eigen::Vector3d slip, dp, tau, gamma, lambda, rate, sinkage;
    Vec qdd;
  };
  auto dynamics = [&](const Vec& q, const Vec& qd, Vec& qdd, Out* out) {
    const Kinematics k = kinematics(g, p, q);
    const Mat H = inertia(k, p);
    const double h = 1e-6;
    const Mat Hdot = (inertia(kinematics(g, p, q + h * qd), p) - inertia(kinematics(g, p, q - h * qd), p)) / (2 * h);
    const Kinematics kp = kinematics(g, p, q + h * qd), km = kinematics(g, p, q - h * qd);
    Vec tau_a = Vec::Zero();
    // Gravity: -dV/dPhi (Eq. 4.37).
    tau_a -= p.gravity * (p.body_mass * k.J_body.row(1) + p.bogie_mass * k.J_bogie.row(1)).transpose();
    Eigen::Matrix<double, 3, N> Psi_q;
    Eigen::Vector3d Psi, Psidot_qd;
    for (int i = 0; i < 3; ++i) {
      tau_a -= p.gravity * p.wheel_mass * k.J_wheel[i].row(1).transpose();
      const Vec2 c = k.wheel[i];
      const Vec2 v = k.J_wheel[i] * qd;
      const Vec2 a = ((kp.J_wheel[i] - km.J_wheel[i]) / (2 * h)) * qd;  // Jdot qdot
      const double z1 = run.path.dz(c.x()), z2 = run.path.ddz(c.x());
      Psi(i) = c.y() - run.path.z(c.x());                                     // Eq. 4.33
      Psi_q.row(i) = k.J_wheel[i].row(1) - z1 * k.J_wheel[i].row(0);
      Psidot_qd(i) = a.y() - z2 * v.x() * v.x() - z1 * a.x();
      // Traction at the wheel (Eq. 4.40-4.47): contact angle from the path's slope.
      const double gamma = std::atan(z1);
      const Vec2 t(std::cos(gamma), std::sin(gamma));
      const double v_t = v.dot(t);
      const double omega = k.W_wheel[i] * qd;  // absolute wheel rate, clockwise = forward rolling
      // Slip (Eq. 2.23) or skid (Eq. 2.26) in the wheel's sense of rotation
      // (a wheel turning backwards sees the mirror image of the forward
      // traction). The steady-state traction of the terramechanics model
      // needs relative motion: it fades in over the first few mm/s of rim or
      // centre speed (tanh), so that a wheel at rest is not turned backwards
      // by its own resistive torque and the forces stay smooth through
      // standstill; a rover sliding back with its wheels still sees full slip.
      const bool after = c.x() >= fx.effect_start_x;
      const TractionModel& model = after ? changed : nominal;
      const double roll_signed = omega * model.wheel.radius;
      const double dir = roll_signed < 0.0 ? -1.0 : 1.0;
      const double fade = std::tanh(std::max(std::abs(roll_signed), std::abs(v_t)) / 0.004);
      const double roll = dir * roll_signed, vt = dir * v_t;
      const double den = std::max({std::abs(roll), std::abs(vt), 1e-6});
      const double s = std::clamp((roll - vt) / den, -1.0, 1.0);
      const double W = normal(i) > 0 ? normal(i) / std::cos(gamma) : 0.0;  // Eq. 4.38, held over the step
      double dp = 0, tr = 0;
      double z = 0;
      traction(model, W, s, dp, tr, out ? &z : nullptr);
      dp *= dir * fade;
      tr *= dir * fade;
      tau_a += k.J_wheel[i].transpose() * (dp * t);            // Eq. 4.43
      tau_a -= k.W_wheel[i].transpose() * tr;                   // Eq. 4.42: resists the wheel's rotation
      tau_a(4 + i) += torque(i) - p.wheel_damping * qd(4 + i);  // Eq. 4.46
      if (out) {
        out->slip(i) = s;
        out->dp(i) = dp;
        out->tau(i) = tr;
        out->gamma(i) = gamma;
        out->rate(i) = omega;
        out->sinkage(i) = z;
      }
    }
    Eigen::Matrix<double, N + 3, N + 3> A = Eigen::Matrix<double, N + 3, N + 3>::Zero();
    A.topLeftCorner<N, N>() = H;
    A.topRightCorner<N, 3>() = Psi_q.transpose();
    A.bottomLeftCorner<3, N>() = Psi_q;
    Eigen::Matrix<double, N + 3, 1> b;
    b.head<N>() = tau_a - Hdot * qd;
    b.tail<3>() = -Psidot_qd - 2 * p.baumgarte_alpha * (Psi_q * qd) - p.baumgarte_beta * p.baumgarte_beta * Psi;  // Eq. 4.17
    const Eigen::Matrix<double, N + 3, 1> x = A.partialPivLu().solve(b);
    qdd = x.head<N>();
    if (out) {
      out->lambda = -x.tail<3>();
      out->qdd = qdd;
    }
  };

  using State = std::vector<double>;
  State s(2 * N, 0.0);
  for (int i = 0; i < N; ++i) s[N + static_cast<std::size_t>(i)] = q(i);
  auto rhs = [&](const State& x, State& dx, double) {
    Vec qq, qd, qdd;
    for (int i = 0; i < N; ++i) {
      qd(i) = x[static_cast<std::size_t>(i)];
      qq(i) = x[N + static_cast<std::size_t>(i)];
    }
    dynamics(qq, qd, qdd, nullptr);
    for (int i = 0; i < N; ++i) {
      dx[static_cast<std::size_t>(i)] = qdd(i);
      dx[N + static_cast<std::size_t>(i)] = qd(i);
    }
  };
  namespace ode = boost::numeric::odeint;
  auto stepper = ode::make_controlled(1e-8, 1e-8, ode::runge_kutta_dopri5<State>());

  const auto steps = static_cast<std::size_t>(std::llround(run.duration * p.control_rate));
  std::vector<double> t(steps + 1);
  std::vector<std::vector<double>> rec(4 + 6 * 3 + 3 + 3, std::vector<double>(steps + 1));
  std::vector<std::vector<double>> geo(8, std::vector<double>(steps + 1));  // bogie pivot x z, wheel centres x z
  // Sensors (Table 5.1): bogie angle, 3 wheel angles, pitch rate, 2 specific
  // forces, forward speed, 3 loads, 3 perpendicular loads.
  std::vector<std::vector<double>> sens(14, std::vector<double>(steps + 1));
  std::mt19937 rng(run.seed);
  std::normal_distribution<double> unit(0.0, 1.0);
  const double deg = M_PI / 180.0;
  auto noise = [&](double sigma) { return run.sensor_noise ? sigma * unit(rng) : 0.0; };
  double step_size = 1e-3;
  for (std::size_t k = 0; k <= steps; ++k) {
    const double time = static_cast<double>(k) * dt;
    Vec qq, qd, qdd;
    for (int i = 0; i < N; ++i) {
      qd(i) = s[static_cast<std::size_t>(i)];
      qq(i) = s[N + static_cast<std::size_t>(i)];
    }
    Out out;
    dynamics(qq, qd, qdd, &out);
    normal = out.lambda;
    const Kinematics kin = kinematics(g, p, qq);
    for (int i = 0; i < 3; ++i) {
      result.max_constraint_error = std::max(result.max_constraint_error, std::abs(kin.wheel[i].y() - run.path.z(kin.wheel[i].x())));
    }
    // Wheel-speed control at the control rate (section 4.2.4) on the wheel
    // rate error (rad/s). Table 4.1's derivative gain is not used: with the
    // torque held over each 20 ms step, Kd = 12.5 on the rate error gives the
    // loop a gain of 12 through the drivetrain's 1.08 kg m^2 and it diverges;
    // the proportional and integral gains alone track the speed.
    for (int i = 0; i < 3; ++i) {
      const double e = p.desired_speed / g.wheel_radius - qd(4 + i);
      integral(i) += e * dt;
      torque(i) = p.kp * e + p.ki * integral(i);
    }
    {
      // Sensor values from the true state; noise of Table 5.1, then the effects.
      const double th = qq(2);
      const Vec2 xb(std::cos(th), -std::sin(th)), zb(std::sin(th), std::cos(th));  // rover axes in the world
      const Vec2 acc(out.qdd(0), out.qdd(1));
      const Vec2 f = acc + Vec2(0.0, p.gravity);  // specific force
      const Vec2 vel(qd(0), qd(1));
      const bool dropped = fx.encoder_dropout_start >= 0 && time >= fx.encoder_dropout_start && time < fx.encoder_dropout_start + 2.0;
      sens[0][k] = qq(3) + noise(9.155e-4 * deg);
      for (int i = 0; i < 3; ++i) {
        const auto ii = static_cast<std::size_t>(i);
        const double reading = qq(4 + i) + noise(2.143e-5 * deg);  // drawn even when dropped: same noise sequence
        sens[1 + ii][k] = dropped && k > 0 ? sens[1 + ii][k - 1] : reading;
      }
      sens[4][k] = qd(2) + noise(0.56 * deg) + fx.gyro_bias;
      sens[5][k] = f.dot(xb) + noise(1.245e-3) + fx.accel_bias;
      sens[6][k] = f.dot(zb) + noise(1.245e-3) + fx.accel_bias;
      sens[7][k] = vel.dot(xb) + noise(1e-3);
      for (int i = 0; i < 3; ++i) {
        // The soil's force on the wheel (normal load and drawbar pull) in the axes of the link carrying it.
        const double gm = out.gamma(i), Wn = normal(i) / std::cos(gm);
        const Vec2 n(-std::sin(gm), std::cos(gm)), tt(std::cos(gm), std::sin(gm));
        const Vec2 F = Wn * n + out.dp(i) * tt;
        const double a = i == 0 ? th : th + qq(3);
        const Vec2 lx(std::cos(a), -std::sin(a)), lz(std::sin(a), std::cos(a));
        const auto ii = static_cast<std::size_t>(i);
        sens[8 + ii][k] = fx.force_scale * F.dot(lz) + fx.force_offset + noise(3.255e-2);
        sens[11 + ii][k] = fx.force_scale * F.dot(lx) + fx.force_offset + noise(3.255e-2);
      }
    }
    {
      const Vec2 pivot = Vec2(qq(0), qq(1)) + rot(qq(2), g.rocker_to_bogie);
      geo[0][k] = pivot.x();
      geo[1][k] = pivot.y();
      for (int i = 0; i < 3; ++i) {
        geo[2 + 2 * static_cast<std::size_t>(i)][k] = kin.wheel[i].x();
        geo[3 + 2 * static_cast<std::size_t>(i)][k] = kin.wheel[i].y();
      }
    }
    t[k] = time;
    rec[0][k] = qq(0);
    rec[1][k] = qq(1);
    rec[2][k] = qq(2);
    rec[3][k] = qq(3);
    for (int i = 0; i < 3; ++i) {
      const auto ii = static_cast<std::size_t>(i);
      rec[4 + ii][k] = out.slip(i);
      rec[7 + ii][k] = normal(i) / std::cos(out.gamma(i));
      rec[10 + ii][k] = out.dp(i);
      rec[13 + ii][k] = out.tau(i);
      rec[16 + ii][k] = out.gamma(i);
      rec[19 + ii][k] = out.rate(i);
      rec[22 + ii][k] = torque(i);
      rec[25 + ii][k] = out.sinkage(i);
    }
    if (k == steps) break;
    ode::integrate_adaptive(stepper, rhs, s, time, time + dt, step_size);
    for (double v : s) {
      if (!std::isfinite(v)) throw DataError("the simulation diverged at t = " + std::to_string(time) + " s");
    }
    if (run.progress && k % 100 == 0) run.progress(static_cast<double>(k) / static_cast<double>(steps));
  }

  log::Log& lg = result.log;
  lg.metadata.rover_id = "kapvik_planar";
  {
    const RockerBogieEffects none;
    auto note = [&](const char* name, double v, double neutral) {
      if (v != neutral) lg.metadata.extra[std::string("truth/effect/") + name] = std::to_string(v);
    };
    note("soil-strength", fx.soil_strength, none.soil_strength);
    note("slip-sinkage", fx.slip_sinkage_n1, none.slip_sinkage_n1);
    note("grousers", fx.grouser_height, none.grouser_height);
    note("wheel-radius-scale", fx.wheel_radius_scale, none.wheel_radius_scale);
    note("effect-start-x", fx.effect_start_x, none.effect_start_x);
    note("gyro-bias", fx.gyro_bias, none.gyro_bias);
    note("accel-bias", fx.accel_bias, none.accel_bias);
    note("force-offset", fx.force_offset, none.force_offset);
    note("force-scale", fx.force_scale, none.force_scale);
    note("encoder-dropout", fx.encoder_dropout_start, none.encoder_dropout_start);
    note("imu-time-offset", fx.imu_time_offset, none.imu_time_offset);
    lg.metadata.extra["truth/seed"] = std::to_string(run.seed);
  }
  {
    log::Stream st("joints", t);
    st.add_channel("bogie_angle", "rad", sens[0], "16-bit absolute encoder");
    for (int i = 0; i < 3; ++i) st.add_channel("wheel_angle_" + std::to_string(i + 1), "rad", sens[1 + static_cast<std::size_t>(i)], "motor encoder");
    lg.add_stream(std::move(st));
  }
  {
    std::vector<double> ti = t;
    for (double& x : ti) x += fx.imu_time_offset;
    log::Stream st("imu", ti);
    st.add_channel("pitch_rate", "rad/s", sens[4], "clockwise positive");
    st.add_channel("specific_force_x", "m/s^2", sens[5], "rover axes: x forward");
    st.add_channel("specific_force_z", "m/s^2", sens[6], "rover axes: z up");
    lg.add_stream(std::move(st));
  }
  {
    log::Stream st("velocimeter", t);
    st.add_channel("forward_speed", "m/s", sens[7], "rover x axis");
    lg.add_stream(std::move(st));
  }
  {
    log::Stream st("forces", t);
    for (int i = 0; i < 3; ++i) st.add_channel("load_" + std::to_string(i + 1), "N", sens[8 + static_cast<std::size_t>(i)], "along the carrying link's z axis");
    for (int i = 0; i < 3; ++i) st.add_channel("perpendicular_" + std::to_string(i + 1), "N", sens[11 + static_cast<std::size_t>(i)], "along the link's x axis");
    lg.add_stream(std::move(st));
  }
  lg.metadata.description = "planar rocker-bogie simulation (seed 003 chapter 4) on path: " + run.path.name;
  lg.metadata.extra["truth/generator"] = "rocker-bogie";
  lg.metadata.extra["truth/soil"] = run.soil.name;
  lg.metadata.extra["truth/traction"] = run.traction == TractionSource::polynomial ? "polynomial" : "wong-reece";
  {
    log::Stream st("truth/pose", t);
    st.add_channel("x", "m", rec[0], "body centre of mass");
    st.add_channel("z", "m", rec[1]);
    st.add_channel("pitch", "rad", rec[2], "clockwise positive (nose down)");
    st.add_channel("bogie_angle", "rad", rec[3], "clockwise positive");
    st.add_channel("bogie_pivot_x", "m", geo[0]);
    st.add_channel("bogie_pivot_z", "m", geo[1]);
    lg.add_stream(std::move(st));
  }
  {
    log::Stream st("truth/wheels", t);
    const char* names[6] = {"slip_", "normal_load_", "drawbar_pull_", "resistive_torque_", "contact_angle_", "wheel_rate_"};
    const char* units[6] = {"1", "N", "N", "N*m", "rad", "rad/s"};
    for (int c = 0; c < 6; ++c) {
      for (int i = 0; i < 3; ++i) {
        st.add_channel(std::string(names[c]) + std::to_string(i + 1), units[c], rec[4 + 3 * static_cast<std::size_t>(c) + static_cast<std::size_t>(i)]);
      }
    }
    for (int i = 0; i < 3; ++i) st.add_channel("sinkage_" + std::to_string(i + 1), "m", rec[25 + static_cast<std::size_t>(i)]);
    for (int i = 0; i < 3; ++i) {
      st.add_channel("centre_x_" + std::to_string(i + 1), "m", geo[2 + 2 * static_cast<std::size_t>(i)], "wheel centre (on the path)");
      st.add_channel("centre_z_" + std::to_string(i + 1), "m", geo[3 + 2 * static_cast<std::size_t>(i)]);
    }
    lg.metadata.extra["truth/wheel_radius_m"] = std::to_string(g.wheel_radius);
    lg.add_stream(std::move(st));
  }
  {
    log::Stream st("commands", t);
    for (int i = 0; i < 3; ++i) st.add_channel("wheel_torque_" + std::to_string(i + 1), "N*m", rec[22 + static_cast<std::size_t>(i)]);
    lg.add_stream(std::move(st));
  }
  if (run.progress) run.progress(1.0);
  return result;
}

}  // namespace roverlab::simulation
