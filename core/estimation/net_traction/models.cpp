#include "core/estimation/net_traction/models.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace roverlab::estimation::net_traction {

namespace rb = simulation::rocker_bogie;
using namespace general;  // NOLINT(google-build-using-namespace): the state indices

double RoverConstants::total_mass() const {
  return parameters.body_mass + parameters.bogie_mass + 3.0 * parameters.wheel_mass;
}

namespace {

// Derivative of the clockwise rotation by `a` applied to v.
Eigen::Vector2d drotate(double s, double c, const Eigen::Vector2d& v) {
  return {-s * v.x() + c * v.y(), -c * v.x() - s * v.y()};
}

}  // namespace

// Eq. 5.19: only pitch and bogie angle matter (wheel masses sit on their
// joints). Eq. 4.29 body by body: m J^T J + I W^T W, where the velocity
// Jacobian columns of pitch and bogie angle are A + B and B (A from the
// body to the bogie pivot, B from the pivot to the point).
ConfigurationTerms configuration_terms(const RoverConstants& rover, double pitch, double bogie) {
  const simulation::RockerBogieParameters& p = rover.parameters;
  const simulation::PlanarRockerBogieGeometry& g = rover.geometry;
  const double s0 = std::sin(pitch), c0 = std::cos(pitch), s1 = std::sin(pitch + bogie), c1 = std::cos(pitch + bogie);
  const Eigen::Vector2d A = drotate(s0, c0, g.rocker_to_bogie);
  ConfigurationTerms t;
  t.sin_pitch = s0;
  t.cos_pitch = c0;
  rb::Mat& H = t.inertia;
  const auto add = [&](double m, double I, const Eigen::Vector2d& pitch_col, const Eigen::Vector2d& bogie_col,
                       bool on_bogie, int wheel) {
    H(0, 0) += m;
    H(1, 1) += m;
    H(0, 2) += m * pitch_col.x();
    H(1, 2) += m * pitch_col.y();
    H(2, 2) += m * pitch_col.squaredNorm() + I;
    t.gravity(2) += p.gravity * m * pitch_col.y();
    if (on_bogie) {
      H(0, 3) += m * bogie_col.x();
      H(1, 3) += m * bogie_col.y();
      H(2, 3) += m * pitch_col.dot(bogie_col) + I;
      H(3, 3) += m * bogie_col.squaredNorm() + I;
      t.gravity(3) += p.gravity * m * bogie_col.y();
    }
    if (wheel >= 0) {
      H(2, 4 + wheel) += I;
      if (on_bogie) H(3, 4 + wheel) += I;
      H(4 + wheel, 4 + wheel) += p.wheel_gear_inertia;  // the drivetrain referred to the wheel
    }
  };
  add(p.body_mass, p.body_inertia, Eigen::Vector2d::Zero(), Eigen::Vector2d::Zero(), false, -1);
  const Eigen::Vector2d B = drotate(s1, c1, p.bogie_com);
  add(p.bogie_mass, p.bogie_inertia, A + B, B, true, -1);
  add(p.wheel_mass, p.wheel_inertia, drotate(s0, c0, g.rocker_to_wheel1), Eigen::Vector2d::Zero(), false, 0);
  const Eigen::Vector2d D2 = drotate(s1, c1, g.bogie_to_wheel2), D3 = drotate(s1, c1, g.bogie_to_wheel3);
  add(p.wheel_mass, p.wheel_inertia, A + D2, D2, true, 1);
  add(p.wheel_mass, p.wheel_inertia, A + D3, D3, true, 2);
  t.gravity(1) = p.gravity * rover.total_mass();
  H.triangularView<Eigen::StrictlyLower>() = H.transpose();
  return t;
}

// Eq. 5.20: the body moves along its own x axis (zdot_0^R = 0).
rb::Vec generalised_velocity(double forward_speed, double pitch, double pitch_rate, double bogie_rate,
                             const Eigen::Vector3d& wheel_rates) {
  rb::Vec v;
  v << forward_speed * std::cos(pitch), -forward_speed * std::sin(pitch), pitch_rate, bogie_rate, wheel_rates;
  return v;
}

// Eq. 2.23 (slip) and 2.26 (skid) in the wheel's sense of rotation.
double slip_ratio(double roll, double speed) {
  const double dir = roll < 0.0 ? -1.0 : 1.0;
  roll *= dir;
  speed *= dir;
  const double den = std::max({std::abs(roll), std::abs(speed), 1e-6});
  return std::clamp((roll - speed) / den, -1.0, 1.0);
}

GeneralProcessModel::GeneralProcessModel(const RoverConstants& rover, double step) : rover_(rover), step_(step) {}

// Eq. 5.24: rows 8-10 of Eq. 4.48 without the small couplings to pitch and bogie.
Eigen::Vector3d GeneralProcessModel::wheel_accelerations(const Eigen::Ref<const Eigen::VectorXd>& x) const {
  const simulation::RockerBogieParameters& p = rover_.parameters;
  return (torques_ - x.segment<3>(kResistiveTorque) - p.wheel_damping * x.segment<3>(kWheelRate)) /
         p.wheel_gear_inertia;
}

const ConfigurationTerms& GeneralProcessModel::terms(double pitch, double bogie) const {
  for (int i = 0; i < cache_size_; ++i) {
    const auto u = static_cast<std::size_t>(i);
    if (cache_key_[u](0) == pitch && cache_key_[u](1) == bogie) return cache_[u];
  }
  const auto slot = static_cast<std::size_t>(cache_next_);
  cache_[slot] = configuration_terms(rover_, pitch, bogie);
  cache_key_[slot] = {pitch, bogie};
  cache_next_ = (cache_next_ + 1) % kCached;
  cache_size_ = std::min(cache_size_ + 1, kCached);
  return cache_[slot];
}

template <class State>
void GeneralProcessModel::operator()(const State& x, State& out) const {
  const double T = step_;
  const ConfigurationTerms& c = terms(x(kPitch), x(kBogie));
  const rb::Mat& H = c.inertia;
  const rb::Vec& dV = c.gravity;
  const Eigen::Vector3d qdd = wheel_accelerations(x);
  const Eigen::Vector3d tau = x.template segment<3>(kResistiveTorque);
  const double th_dd = x(kPitchAcceleration), q1_dd = x(kBogieAcceleration);
  const double x_dd = x(kAccelerationX), z_dd = x(kAccelerationZ);
  out = x;                                               // Eq. 5.25, 5.34, 5.36: random walks
  out.template segment<3>(kWheelRate) += qdd * T;        // Eq. 5.23
  out(kPitch) += x(kPitchRate) * T + th_dd * T * T / 2;  // Eq. 5.26
  out(kBogie) += x(kBogieRate) * T + q1_dd * T * T / 2;  // Eq. 5.27
  out(kPitchRate) += th_dd * T;                          // Eq. 5.28
  out(kBogieRate) += q1_dd * T;                          // Eq. 5.29
  out(kPitchAcceleration) = (x(kMomentBody) - tau.sum() - dV(2) - H(2, 0) * x_dd - H(2, 1) * z_dd -  // Eq. 5.30
                             H(2, 3) * q1_dd - H(2, 4) * qdd(0) - H(2, 5) * qdd(1) - H(2, 6) * qdd(2)) /
                            H(2, 2);
  out(kBogieAcceleration) = (x(kMomentBogie) - tau(1) - tau(2) - dV(3) - H(3, 0) * x_dd - H(3, 1) * z_dd -  // Eq. 5.31
                             H(3, 2) * th_dd - H(3, 5) * qdd(1) - H(3, 6) * qdd(2)) /
                            H(3, 3);
  out(kAccelerationX) = (x(kForceX) - H(0, 2) * th_dd - H(0, 3) * q1_dd) / H(0, 0);          // Eq. 5.32
  out(kAccelerationZ) = (x(kForceZ) - dV(1) - H(1, 2) * th_dd - H(1, 3) * q1_dd) / H(1, 1);  // Eq. 5.33
  out(kForwardSpeed) += (x_dd * c.cos_pitch - z_dd * c.sin_pitch) * T;                       // Eq. 5.35
}

template void GeneralProcessModel::operator()(const Eigen::VectorXd&, Eigen::VectorXd&) const;
template void GeneralProcessModel::operator()(const GeneralState&, GeneralState&) const;

template <class State, class Measurement>
void GeneralMeasurementModel::operator()(const State& x, Measurement& out) const {
  const double th = x(kPitch);
  if (!(th == pitch_)) {
    pitch_ = th;
    sin_ = std::sin(th);
    cos_ = std::cos(th);
  }
  const double c = cos_, s = sin_;
  const double x_dd = x(kAccelerationX), z_dd = x(kAccelerationZ);
  out.resize(kMeasurements);
  out.template head<3>() = x.template segment<3>(kWheelRate);  // Eq. 5.44
  out(3) = th;
  out(4) = x(kBogie);
  out(5) = x_dd * c - z_dd * s - gravity_ * s;  // Eq. 5.45
  out(6) = x_dd * s + z_dd * c + gravity_ * c;  // Eq. 5.46
  out(7) = x(kForwardSpeed);
  out.template tail<3>() = x.template segment<3>(kSlip);  // Eq. 5.47
}

template void GeneralMeasurementModel::operator()(const Eigen::VectorXd&, Eigen::VectorXd&) const;
template void GeneralMeasurementModel::operator()(const GeneralState&, GeneralMeasurement&) const;

GeneralMeasurement general_measurement(const RoverConstants& rover, const SensorSample& now, const SensorSample& before,
                                       double step, const Eigen::Vector2d* rates) {
  GeneralMeasurement y;
  const Eigen::Vector3d wheel_rates = (now.wheel_angle - before.wheel_angle) / step;  // Eq. 5.38
  const double pitch = std::atan2(-now.specific_force_x, now.specific_force_z);       // Eq. 5.39
  const double pitch_rate = rates != nullptr ? (*rates)(0) : now.pitch_rate;
  const double bogie_rate = rates != nullptr ? (*rates)(1) : (now.bogie - before.bogie) / step;
  y.head<3>() = wheel_rates;
  y(3) = pitch;
  y(4) = now.bogie;
  y(5) = now.specific_force_x;
  y(6) = now.specific_force_z;
  y(7) = now.forward_speed;
  // Eq. 5.40-5.42: wheel centre velocities from the measured configuration.
  const rb::Vec v = generalised_velocity(now.forward_speed, pitch, pitch_rate, bogie_rate, wheel_rates);
  rb::Vec q = rb::Vec::Zero();
  q(2) = pitch;
  q(3) = now.bogie;
  const rb::Kinematics k = rb::kinematics(rover.geometry, rover.parameters, q);
  for (int i = 0; i < 3; ++i) {
    const Eigen::Vector2d c = k.J_wheel[i] * v;
    const double speed = (c.x() < 0 ? -1.0 : 1.0) * c.norm();
    // The wheel's absolute rate (the seed neglects the pitch and bogie
    // rates here; the simulator's slip includes them).
    const double roll = (k.W_wheel[i] * v)(0) * rover.geometry.wheel_radius;
    y(8 + i) = std::max(std::abs(roll), std::abs(speed)) < 1e-3 ? std::numeric_limits<double>::quiet_NaN()
                                                                : slip_ratio(roll, speed);
  }
  return y;
}

Eigen::Vector3d sensor_angles(double pitch, double bogie) { return {pitch, pitch + bogie, pitch + bogie}; }

// Eq. 5.57-5.59 with the simulator's signs: the soil's force W n + DP t,
// n = (-sin g, cos g), t = (cos g, sin g), seen along the link's z axis
// (sin a, cos a) and x axis (cos a, -sin a).
template <class State, class Measurement>
void ForceMeasurementModel::operator()(const State& x, Measurement& out) const {
  out.resize(wheel_force::kMeasurements);
  for (int i = 0; i < 3; ++i) {
    const double g = x(wheel_force::kContactAngle + i), W = x(wheel_force::kNormalLoad + i),
                 dp = x(wheel_force::kDrawbarPull + i);
    const double a = g + angles_(i);
    const auto u = static_cast<std::size_t>(i);
    if (!(a == angle_[u])) {
      angle_[u] = a;
      sin_[u] = std::sin(a);
      cos_[u] = std::cos(a);
    }
    const double c = cos_[u], s = sin_[u];
    out(i) = g;                    // Eq. 5.57
    out(3 + i) = W * c + dp * s;   // Eq. 5.58
    out(6 + i) = -W * s + dp * c;  // Eq. 5.59
  }
}

template void ForceMeasurementModel::operator()(const Eigen::VectorXd&, Eigen::VectorXd&) const;
template void ForceMeasurementModel::operator()(const WheelForceState&, WheelForceMeasurement&) const;

// Eq. 5.54-5.56 on Estimator 1's estimate.
Eigen::Vector3d contact_angle_measurement(const RoverConstants& rover, const Eigen::Ref<const Eigen::VectorXd>& x) {
  const rb::Vec v =
      generalised_velocity(x(kForwardSpeed), x(kPitch), x(kPitchRate), x(kBogieRate), x.segment<3>(kWheelRate));
  rb::Vec q = rb::Vec::Zero();
  q(2) = x(kPitch);
  q(3) = x(kBogie);
  const rb::Kinematics k = rb::kinematics(rover.geometry, rover.parameters, q);
  Eigen::Vector3d gamma;
  for (int i = 0; i < 3; ++i) {
    const Eigen::Vector2d c = k.J_wheel[i] * v;
    gamma(i) = std::abs(c.x()) < 1e-4 ? std::numeric_limits<double>::quiet_NaN() : std::atan(c.y() / c.x());
  }
  return gamma;
}

// Eq. 5.63-5.66: the bogie's moment from wheels 2 and 3 is
// sum(F_perp l_z - F_L l_x) over their links' vectors l; the net horizontal
// force sum(F_perp cos a + F_L sin a) over all three.
Eigen::Vector3d perpendicular_from_net_forces(const RoverConstants& rover, const Eigen::Ref<const Eigen::VectorXd>& x,
                                              const Eigen::Vector3d& loads) {
  const auto& g = rover.geometry;
  const double lz = 0.5 * (g.bogie_to_wheel2.y() + g.bogie_to_wheel3.y());
  const double bogie_sum =
      (x(kMomentBogie) + loads(1) * g.bogie_to_wheel2.x() + loads(2) * g.bogie_to_wheel3.x()) / lz;  // Eq. 5.64
  const Eigen::Vector3d a = sensor_angles(x(kPitch), x(kBogie));
  Eigen::Vector3d perp;
  perp(0) = (x(kForceX) - loads(0) * std::sin(a(0)) - bogie_sum * std::cos(a(1)) -  // Eq. 5.65
             (loads(1) + loads(2)) * std::sin(a(1))) /
            std::cos(a(0));
  const double both = loads(1) + loads(2);
  const double share = std::abs(both) > 1e-6 ? loads(1) / both : 0.5;  // Eq. 5.66
  perp(1) = bogie_sum * share;
  perp(2) = bogie_sum * (1.0 - share);
  return perp;
}

// Eq. 5.66 refined by a drawbar-pull shape: F_perp,i = F_L,i (mu_i - t) /
// (1 + mu_i t) (Eq. 5.58-5.59 divided), t = tan(a) of the bogie wheels'
// common angle a, mu_i = shape(W_i, s_i) / W_i + delta, delta solved by
// Newton for Eq. 5.64's sum.
Eigen::Vector3d perpendicular_from_net_forces(const RoverConstants& rover, const Eigen::Ref<const Eigen::VectorXd>& x,
                                              const Eigen::Vector3d& loads, const Eigen::Vector3d& contact_angles,
                                              const DrawbarPullShape& shape) {
  Eigen::Vector3d perp = perpendicular_from_net_forces(rover, x, loads);  // Eq. 5.64-5.66
  if (!shape || !std::isfinite(contact_angles(1)) || !std::isfinite(contact_angles(2))) return perp;
  const double sum = perp(1) + perp(2);
  const double a = 0.5 * (contact_angles(1) + contact_angles(2)) + sensor_angles(x(kPitch), x(kBogie))(1);
  const double t = std::tan(a);
  double m[2], fl[2];
  for (int j = 0; j < 2; ++j) {
    const int i = j + 1;
    const double load = loads(i) * std::cos(a) - perp(i) * std::sin(a);  // W of Eq. 5.66's split
    if (!(load > 1.0)) return perp;
    m[j] = shape(load, x(kSlip + i)) / load;
    if (!(std::abs(m[j]) < 1.0)) return perp;
    fl[j] = loads(i);
  }
  double delta = 0.0, g = -sum;
  Eigen::Vector2d split = perp.tail<2>();
  for (int it = 0; it < 8; ++it) {
    g = -sum;
    double dg = 0;
    for (int j = 0; j < 2; ++j) {
      const double mu = m[j] + delta, den = 1.0 + mu * t;
      split(j) = fl[j] * (mu - t) / den;
      g += split(j);
      dg += fl[j] * (1.0 + t * t) / (den * den);
    }
    if (std::abs(g) < 1e-9 * (1.0 + std::abs(sum)) || !(std::abs(dg) > 1e-12)) break;
    delta -= g / dg;
  }
  const bool solved = split.allFinite() && std::abs(g) < 1e-6 * (1.0 + std::abs(sum)) && std::abs(m[0] + delta) < 1.0 &&
                      std::abs(m[1] + delta) < 1.0;
  if (solved) perp.tail<2>() = split;
  return perp;
}

}  // namespace roverlab::estimation::net_traction
