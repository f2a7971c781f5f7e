#include "core/models/ins.h"

#include <cmath>

namespace roverlab::estimation {

namespace {
constexpr double kSemiMajor = 6378137.0;             // WGS-84 a, m
constexpr double kEccentricity2 = 6.69437999014e-3;  // WGS-84 e^2
constexpr double kEarthRate = 7.292115e-5;           // rad/s
}  // namespace

double meridian_radius(double L) {
  const double s = std::sin(L);
  return kSemiMajor * (1.0 - kEccentricity2) / std::pow(1.0 - kEccentricity2 * s * s, 1.5);
}

double transverse_radius(double L) {
  const double s = std::sin(L);
  return kSemiMajor / std::sqrt(1.0 - kEccentricity2 * s * s);
}

double gravity_down(double L, double h) {
  const double s2 = std::sin(L) * std::sin(L);
  const double g0 = 9.7803253359 * (1.0 + 0.001931853 * s2) / std::sqrt(1.0 - kEccentricity2 * s2);
  return g0 * (1.0 - 2.0 * h / kSemiMajor);  // free-air correction, adequate near the surface
}

Eigen::Matrix3d skew(const Eigen::Vector3d& v) {
  Eigen::Matrix3d m;
  m << 0.0, -v.z(), v.y(), v.z(), 0.0, -v.x(), -v.y(), v.x(), 0.0;
  return m;
}

Eigen::Vector3d euler_from_dcm(const Eigen::Matrix3d& C) {
  // Eq. 25 of seed 002 on C_n^b = C_bn^T.
  const Eigen::Matrix3d Cnb = C.transpose();
  return {std::atan2(Cnb(1, 2), Cnb(2, 2)), -std::asin(std::clamp(Cnb(0, 2), -1.0, 1.0)),
          std::atan2(Cnb(0, 1), Cnb(0, 0))};
}

Eigen::Matrix3d dcm_from_euler(double roll, double pitch, double yaw) {
  return (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

namespace {

Eigen::Vector3d earth_rate_n(double L) { return {kEarthRate * std::cos(L), 0.0, -kEarthRate * std::sin(L)}; }

Eigen::Vector3d transport_rate_n(const InsState& s) {
  const double rn = meridian_radius(s.latitude) + s.height, re = transverse_radius(s.latitude) + s.height;
  return {s.v_n.y() / re, -s.v_n.x() / rn, -s.v_n.y() * std::tan(s.latitude) / re};
}

Eigen::Matrix3d exp_so3(const Eigen::Vector3d& phi) {
  const double angle = phi.norm();
  if (angle < 1e-12) return Eigen::Matrix3d::Identity() + skew(phi);
  return Eigen::AngleAxisd(angle, phi / angle).toRotationMatrix();
}

}  // namespace

void mechanize(InsState& s, const Eigen::Vector3d& f_b, const Eigen::Vector3d& w_b, double dt, const InsOptions& o) {
  const Eigen::Vector3d w_ie = o.earth_rotation ? earth_rate_n(s.latitude) : Eigen::Vector3d::Zero();
  const Eigen::Vector3d w_en = o.transport_rate ? transport_rate_n(s) : Eigen::Vector3d::Zero();
  // Eq. 2, with the body rotation taken exactly (exponential map) rather than to first order.
  const Eigen::Matrix3d C_old = s.C_bn;
  s.C_bn = exp_so3(-(w_ie + w_en) * dt) * C_old * exp_so3(w_b * dt);
  // Eq. 3: specific force resolved with the mean attitude over the step.
  const Eigen::Vector3d f_n = 0.5 * (C_old + s.C_bn) * f_b;
  const Eigen::Vector3d g_n(0.0, 0.0, gravity_down(s.latitude, s.height));
  const Eigen::Vector3d v_old = s.v_n;
  s.v_n = v_old + (f_n + g_n - (skew(w_en) + 2.0 * skew(w_ie)) * v_old) * dt;
  // Eq. 4-6: trapezoidal position update.
  const double h_old = s.height, L_old = s.latitude;
  s.height = h_old - 0.5 * dt * (v_old.z() + s.v_n.z());
  s.latitude =
      L_old +
      0.5 * dt * (v_old.x() / (meridian_radius(L_old) + h_old) + s.v_n.x() / (meridian_radius(L_old) + s.height));
  s.longitude += 0.5 * dt *
                 (v_old.y() / ((transverse_radius(L_old) + h_old) * std::cos(L_old)) +
                  s.v_n.y() / ((transverse_radius(s.latitude) + s.height) * std::cos(s.latitude)));
}

Eigen::Matrix<double, 15, 15> error_system_matrix(const InsState& s, const Eigen::Vector3d& f_b, const InsOptions& o) {
  using M3 = Eigen::Matrix3d;
  Eigen::Matrix<double, 15, 15> F = Eigen::Matrix<double, 15, 15>::Zero();
  const double rn = meridian_radius(s.latitude) + s.height, re = transverse_radius(s.latitude) + s.height;
  const Eigen::Vector3d w_ie = o.earth_rotation ? earth_rate_n(s.latitude) : Eigen::Vector3d::Zero();
  const Eigen::Vector3d w_en = o.transport_rate ? transport_rate_n(s) : Eigen::Vector3d::Zero();
  // Attitude error: d(dpsi)/dt = -[w_in x] dpsi - C_bn d(b_g)  (F11, F15)
  F.block<3, 3>(0, 0) = -skew(w_ie + w_en);
  F.block<3, 3>(0, 12) = -s.C_bn;
  // Velocity error: -[f_n x] dpsi - (coriolis) dv + gravity gradient dh - C_bn d(b_a)  (F21, F22, F23, F24)
  F.block<3, 3>(3, 0) = -skew(s.C_bn * f_b);
  F.block<3, 3>(3, 3) = -skew(w_en + 2.0 * w_ie);
  F(5, 8) = -2.0 * gravity_down(s.latitude, s.height) / kSemiMajor;  // dg_D/dh with h up: g falls with height
  F.block<3, 3>(3, 9) = -s.C_bn;
  // Position error (lat, lon, h): F32
  M3 F32 = M3::Zero();
  F32(0, 0) = 1.0 / rn;
  F32(1, 1) = 1.0 / (re * std::cos(s.latitude));
  F32(2, 2) = -1.0;
  F.block<3, 3>(6, 3) = F32;
  return F;
}

void correct(InsState& s, const Eigen::Matrix<double, 15, 1>& dx) {
  s.C_bn = exp_so3(dx.segment<3>(0)) * s.C_bn;  // C_true = (I + [dpsi x]) C_est, Eq. 24
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(s.C_bn, Eigen::ComputeFullU | Eigen::ComputeFullV);
  s.C_bn = svd.matrixU() * svd.matrixV().transpose();
  s.v_n += dx.segment<3>(3);  // Eq. 26
  s.latitude += dx(6);        // Eq. 27
  s.longitude += dx(7);
  s.height += dx(8);
  s.accel_bias += dx.segment<3>(9);
  s.gyro_bias += dx.segment<3>(12);
}

}  // namespace roverlab::estimation
