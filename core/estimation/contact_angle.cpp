#include "core/estimation/contact_angle.h"

#include <ceres/jet.h>

#include <algorithm>
#include <cmath>

#include "core/common/error.h"
#include "core/estimation/nonlinear_filter.h"

namespace roverlab::estimation {

using kinematics::Vec3;

ContactModel parse_contact_model(const std::string& s) {
  if (s == "smooth") return ContactModel::smooth;
  if (s == "c") return ContactModel::contact;
  if (s == "c+ss") return ContactModel::contact_side_slip;
  throw DataError("model '" + s + "': expected smooth, c or c+ss");
}

FilterKind parse_filter_kind(const std::string& s) {
  if (s == "ekf") return FilterKind::ekf;
  if (s == "ukf") return FilterKind::ukf;
  throw DataError("filter '" + s + "': expected ekf or ukf");
}

AngleModel parse_angle_model(const std::string& s) {
  if (s == "random-walk") return AngleModel::random_walk;
  if (s == "damped") return AngleModel::damped;
  throw DataError("angle model '" + s + "': expected random-walk or damped");
}

namespace {

// Inputs of one step.
struct Inputs {
  Eigen::Vector3d gyro, accel;
  std::vector<double> q, qdot, wheel_rate;
};

// Eq. 4.14 and 4.13 (discretised as Eq. 4.17): attitude and velocity at the
// next step. theta = (psi, theta, phi).
template <class T>
void strapdown(const T* att, const T* v, const T* n_att, const T* n_v, const T* n_f, const T* n_w, const Inputs& in,
               const Eigen::Vector3d& g_i, double ts, T* att_next, T* v_next) {
  using std::cos;
  using std::sin;
  const T w[3] = {T(in.gyro.x()) - n_w[0], T(in.gyro.y()) - n_w[1], T(in.gyro.z()) - n_w[2]};
  const T psi = att[0], th = att[1], ph = att[2];
  const T cth = cos(th), sth = sin(th), cph = cos(ph), sph = sin(ph), cps = cos(psi), sps = sin(psi);
  // Eq. 4.14.
  const T d_psi = (sph * w[1] + cph * w[2]) / cth;
  const T d_th = cph * w[1] - sph * w[2];
  const T d_ph = w[0] + (sth * sph * w[1] + sth * cph * w[2]) / cth;
  att_next[0] = psi + d_psi * ts + n_att[0];
  att_next[1] = th + d_th * ts + n_att[1];
  att_next[2] = ph + d_ph * ts + n_att[2];
  // R_g^i = Rz(psi) Ry(theta) Rx(phi); gravity in g is R_g^i^T g^i.
  const T R[3][3] = {{cps * cth, cps * sth * sph - sps * cph, cps * sth * cph + sps * sph},
                     {sps * cth, sps * sth * sph + cps * cph, sps * sth * cph - cps * sph},
                     {-sth, cth * sph, cth * cph}};
  T g_g[3];
  for (int k = 0; k < 3; ++k) g_g[k] = R[0][k] * g_i.x() + R[1][k] * g_i.y() + R[2][k] * g_i.z();
  // Eq. 4.13: v' = -w x v + f - g.
  const T wxv[3] = {w[1] * v[2] - w[2] * v[1], w[2] * v[0] - w[0] * v[2], w[0] * v[1] - w[1] * v[0]};
  for (int k = 0; k < 3; ++k) {
    const T dv = -wxv[k] + (T(in.accel[k]) - n_f[k]) - g_g[k];
    v_next[k] = v[k] + dv * ts + n_v[k];
  }
}

// One wheel's three measurements (Eq. 4.20 / Table 5.1): wheel rate and
// the lateral and normal velocity in the final frame.
template <class T>
void wheel_measurement(const kinematics::RoverModel& m, int wheel, kinematics::WheelFrame frame, const T* v,
                       const T& slip, const T& gamma, const T& beta, const T* n_w, const T& q_b, const T& q_s,
                       const T& qd_b, const T& qd_s, const Inputs& in, T out[3]) {
  const std::size_t nq = m.joints.size();
  T q[16], qd[16];
  for (std::size_t j = 0; j < nq; ++j) {
    q[j] = T(in.q[j]);
    qd[j] = T(in.qdot[j]);
  }
  const auto& c = m.wheels[static_cast<std::size_t>(wheel)];
  if (c.bogie_joint >= 0) {
    q[c.bogie_joint] = q_b;
    qd[c.bogie_joint] = qd_b;
  }
  if (c.steer_joint >= 0) {
    q[c.steer_joint] = q_s;
    qd[c.steer_joint] = qd_s;
  }
  const Vec3<T> vel(v[0], v[1], v[2]);
  const Vec3<T> w(T(in.gyro.x()) - n_w[0], T(in.gyro.y()) - n_w[1], T(in.gyro.z()) - n_w[2]);
  const Vec3<T> u = kinematics::wheel_velocity<T>(m, wheel, q, qd, vel, w, gamma, beta, frame);
  using std::cos;
  const T scale = frame == kinematics::WheelFrame::side_slip ? cos(beta) : T(1.0);
  out[0] = scale * u.x() / ((T(1.0) - slip) * m.wheel_radius);
  out[1] = u.y();
  out[2] = u.z();
}

struct Layout {
  int na = 0;  // angle states per wheel set: 0, 6 or 12
  int nw = 6, nq = 9;
  int nx() const { return 12 + na; }
  int np() const { return nx() + 6; }  // n_att, n_v, n_s, n_gamma, n_beta, n_f, n_w
  int ny() const { return 3 * nw; }
  int nm() const { return 3 + nw + 2 * nq + 2 * nw; }  // n_w(gyro), n_wheel, n_q, n_qdot, n_vy, n_vz
};

}  // namespace

ContactAngleResult run_contact_angle(const log::Log& lg, const kinematics::RoverModel& m, const ContactAngleOptions& o) {
  if (m.wheels.size() != 6) throw DataError("rover " + m.name + ": the estimator expects six wheels");
  if (m.joints.size() > 16) throw DataError("rover " + m.name + ": more than 16 joints");
  const log::Stream& imu = lg.stream("imu");
  const log::Stream& joints = lg.stream("joints");
  const log::Stream& wheels = lg.stream("wheels");
  if (imu.size() < 10) throw DataError("stream 'imu' has fewer than 10 samples");
  const char* imu_names[6] = {"angular_rate_x", "angular_rate_y", "angular_rate_z", "specific_force_x", "specific_force_y", "specific_force_z"};
  std::vector<const std::vector<double>*> imu_ch, q_ch, qd_ch, w_ch;
  for (const char* c : imu_names) imu_ch.push_back(&imu.channel(c).values);
  for (const auto& j : m.joints) {
    q_ch.push_back(&joints.channel(j).values);
    qd_ch.push_back(&joints.channel(j + "_rate").values);
  }
  for (const auto& w : m.wheels) w_ch.push_back(&wheels.channel("rate_" + w.name).values);

  Layout L;
  L.na = o.model == ContactModel::smooth ? 0 : o.model == ContactModel::contact ? 6 : 12;
  L.nq = static_cast<int>(m.joints.size());
  const kinematics::WheelFrame frame = o.model == ContactModel::smooth ? kinematics::WheelFrame::drive
                                       : o.model == ContactModel::contact ? kinematics::WheelFrame::contact
                                                                          : kinematics::WheelFrame::side_slip;
  const int nx = L.nx(), np = L.np(), ny = L.ny(), nm = L.nm(), nq = L.nq, nw = L.nw;
  const auto& t = imu.time();
  const std::size_t n = t.size();

  // Homing: attitude by levelling and the gravity vector g^i from the first 0.5 s.
  Eigen::Vector3d f0 = Eigen::Vector3d::Zero();
  std::size_t h = 0;
  while (h < n && t[h] - t[0] < 0.5) {
    f0 += Eigen::Vector3d((*imu_ch[3])[h], (*imu_ch[4])[h], (*imu_ch[5])[h]);
    ++h;
  }
  f0 /= static_cast<double>(std::max<std::size_t>(h, 1));
  const double pitch0 = std::atan2(-f0.x(), std::hypot(f0.y(), f0.z()));  // z up: f = R^T (0, 0, g)
  const double roll0 = std::atan2(f0.y(), f0.z());
  const Eigen::Vector3d g_i(0.0, 0.0, f0.norm());

  // Noise covariances.
  Eigen::VectorXd qdiag(np);
  qdiag.segment(0, 3).setConstant(o.attitude_variance);
  qdiag.segment(3, 3).setConstant(o.velocity_variance);
  qdiag.segment(6, 6).setConstant(o.slip_variance);
  if (L.na > 0) qdiag.segment(12, L.na).setConstant(o.angle_variance);
  qdiag.segment(nx, 3) = m.noise.accelerometer;
  qdiag.segment(nx + 3, 3) = m.noise.gyro;
  const Eigen::MatrixXd Q = qdiag.asDiagonal();
  Eigen::VectorXd rdiag(nm);
  rdiag.segment(0, 3) = m.noise.gyro;
  std::vector<double> q_var(static_cast<std::size_t>(nq), 1e-12), qd_var(static_cast<std::size_t>(nq), 1e-12);
  {
    std::size_t b = 0;
    for (int j = 0; j < nq; ++j) {
      if (m.joints[static_cast<std::size_t>(j)].rfind("bogie", 0) == 0 && b < m.noise.bogie_angle.size()) {
        q_var[static_cast<std::size_t>(j)] = m.noise.bogie_angle[b];
        qd_var[static_cast<std::size_t>(j)] = m.noise.bogie_rate[b];
        ++b;
      }
    }
    for (int w = 0; w < nw; ++w) {
      const int j = m.wheels[static_cast<std::size_t>(w)].steer_joint;
      if (j >= 0 && !m.noise.steer_angle.empty()) {
        q_var[static_cast<std::size_t>(j)] = m.noise.steer_angle[static_cast<std::size_t>(w)];
        qd_var[static_cast<std::size_t>(j)] = m.noise.steer_rate[static_cast<std::size_t>(w)];
      }
    }
  }
  for (int w = 0; w < nw; ++w) {
    rdiag(3 + w) = m.noise.wheel_rate.empty() ? 1e-12 : m.noise.wheel_rate[static_cast<std::size_t>(w)];
  }
  for (int j = 0; j < nq; ++j) {
    rdiag(3 + nw + j) = q_var[static_cast<std::size_t>(j)];
    rdiag(3 + nw + nq + j) = qd_var[static_cast<std::size_t>(j)];
  }
  rdiag.segment(3 + nw + 2 * nq, 2 * nw).setConstant(o.lateral_variance);

  // Joint rates fused with the slope of the joint angles (offline extension).
  std::vector<std::vector<double>> fused_rate;
  std::vector<double> fused_var = qd_var;
  if (o.joint_rate_window > 0.0) {
    const auto& tj = joints.time();
    const std::size_t nj = tj.size();
    const double rate_hz = joints.mean_rate_hz();
    const auto half = static_cast<std::size_t>(std::max(1.0, 0.5 * o.joint_rate_window * rate_hz));
    for (int j = 0; j < nq; ++j) {
      const auto& qa = *q_ch[static_cast<std::size_t>(j)];
      const auto& qr = *qd_ch[static_cast<std::size_t>(j)];
      // Slope variance of a line through N points spaced dt: 12 var_q / (N (N^2 - 1) dt^2).
      const double N = static_cast<double>(2 * half + 1), dt = 1.0 / rate_hz;
      const double slope_var = 12.0 * q_var[static_cast<std::size_t>(j)] / (N * (N * N - 1.0) * dt * dt);
      const double mv = qd_var[static_cast<std::size_t>(j)];
      const double w_slope = mv / (mv + slope_var);
      fused_var[static_cast<std::size_t>(j)] = mv * slope_var / (mv + slope_var);
      std::vector<double> out(nj);
      for (std::size_t i = 0; i < nj; ++i) {
        const std::size_t a = i > half ? i - half : 0, b = std::min(nj - 1, i + half);
        double st = 0, sq = 0, stt = 0, stq = 0;
        const double m_ = static_cast<double>(b - a + 1);
        for (std::size_t k = a; k <= b; ++k) {
          const double x = tj[k] - tj[i];
          st += x;
          sq += qa[k];
          stt += x * x;
          stq += x * qa[k];
        }
        const double den = m_ * stt - st * st;
        const double slope = den > 0 ? (m_ * stq - st * sq) / den : qr[i];
        out[i] = w_slope * slope + (1.0 - w_slope) * qr[i];
      }
      fused_rate.push_back(std::move(out));
    }
    for (int j = 0; j < nq; ++j) rdiag(3 + nw + nq + j) = fused_var[static_cast<std::size_t>(j)];
  }
  const Eigen::MatrixXd R_used = rdiag.asDiagonal();

  auto inputs_at = [&](std::size_t i) {
    Inputs in;
    in.gyro = Eigen::Vector3d((*imu_ch[0])[i], (*imu_ch[1])[i], (*imu_ch[2])[i]);
    in.accel = Eigen::Vector3d((*imu_ch[3])[i], (*imu_ch[4])[i], (*imu_ch[5])[i]);
    const std::size_t kj = std::min(joints.nearest_index(t[i]), joints.size() - 1);
    const std::size_t kw = std::min(wheels.nearest_index(t[i]), wheels.size() - 1);
    for (int j = 0; j < nq; ++j) {
      in.q.push_back((*q_ch[static_cast<std::size_t>(j)])[kj]);
      in.qdot.push_back(fused_rate.empty() ? (*qd_ch[static_cast<std::size_t>(j)])[kj] : fused_rate[static_cast<std::size_t>(j)][kj]);
    }
    for (int w = 0; w < nw; ++w) in.wheel_rate.push_back((*w_ch[static_cast<std::size_t>(w)])[kw]);
    for (double v : in.q) {
      if (!std::isfinite(v)) throw DataError("stream 'joints': missing sample at t = " + std::to_string(t[i]) + " s");
    }
    if (!std::isfinite(in.gyro.sum() + in.accel.sum())) {
      throw DataError("stream 'imu': missing sample at t = " + std::to_string(t[i]) + " s");
    }
    return in;
  };

  const double angle_keep = o.angle_model == AngleModel::damped ? 1.0 : 0.0;  // multiplies -A ts
  // Process model in double (UKF) and linearised with Jets (EKF).
  auto f_double = [&](const Eigen::VectorXd& x, const Eigen::VectorXd& nz, const Inputs& in, double ts) {
    Eigen::VectorXd y(nx);
    strapdown<double>(x.data(), x.data() + 3, nz.data(), nz.data() + 3, nz.data() + nx, nz.data() + nx + 3, in, g_i, ts,
                      y.data(), y.data() + 3);
    for (int k = 0; k < 6; ++k) y(6 + k) = x(6 + k) * (1.0 - o.slip_damping * ts) + nz(6 + k);  // Eq. 4.15
    for (int k = 0; k < L.na; ++k) {
      y(12 + k) = x(12 + k) * (1.0 - angle_keep * o.angle_damping * ts) + nz(12 + k);  // Eq. 5.3-5.6
    }
    return y;
  };
  auto f_linear = [&](const Eigen::VectorXd& x, const Inputs& in, double ts) {
    using J = ceres::Jet<double, 18>;
    J a[3], v[3], na[3], nv[3], nf[3], nw3[3], an[3], vn[3];
    for (int k = 0; k < 3; ++k) {
      a[k] = J(x(k), k);
      v[k] = J(x(3 + k), 3 + k);
      na[k] = J(0.0, 6 + k);
      nv[k] = J(0.0, 9 + k);
      nf[k] = J(0.0, 12 + k);
      nw3[k] = J(0.0, 15 + k);
    }
    strapdown<J>(a, v, na, nv, nf, nw3, in, g_i, ts, an, vn);
    Linearized r;
    r.value = f_double(x, Eigen::VectorXd::Zero(np), in, ts);
    r.dx = Eigen::MatrixXd::Zero(nx, nx);
    r.dn = Eigen::MatrixXd::Zero(nx, np);
    for (int k = 0; k < 3; ++k) {
      for (int c = 0; c < 6; ++c) {
        r.dx(k, c) = an[k].v[c];
        r.dx(3 + k, c) = vn[k].v[c];
      }
      for (int c = 0; c < 6; ++c) {  // n_att, n_v
        r.dn(k, c) = an[k].v[6 + c];
        r.dn(3 + k, c) = vn[k].v[6 + c];
      }
      for (int c = 0; c < 6; ++c) {  // n_f, n_w
        r.dn(k, nx + c) = an[k].v[12 + c];
        r.dn(3 + k, nx + c) = vn[k].v[12 + c];
      }
    }
    for (int k = 0; k < 6; ++k) {
      r.dx(6 + k, 6 + k) = 1.0 - o.slip_damping * ts;
      r.dn(6 + k, 6 + k) = 1.0;
    }
    for (int k = 0; k < L.na; ++k) {
      r.dx(12 + k, 12 + k) = 1.0 - angle_keep * o.angle_damping * ts;
      r.dn(12 + k, 12 + k) = 1.0;
    }
    return r;
  };
  // Measurement model. Noise order: n_w (gyro 3), n_wheel (6), n_q, n_qdot, n_vy (6), n_vz (6).
  auto h_double = [&](const Eigen::VectorXd& x, const Eigen::VectorXd& nz, const Inputs& in) {
    Eigen::VectorXd y(ny);
    for (int w = 0; w < nw; ++w) {
      const auto& c = m.wheels[static_cast<std::size_t>(w)];
      const double g = L.na >= 6 ? x(12 + w) : 0.0, b = L.na >= 12 ? x(18 + w) : 0.0;
      auto qv = [&](int j, bool rate) {
        if (j < 0) return 0.0;
        return (rate ? in.qdot : in.q)[static_cast<std::size_t>(j)] - nz(3 + nw + (rate ? nq : 0) + j);
      };
      double out[3];
      wheel_measurement<double>(m, w, frame, x.data() + 3, x(6 + w), g, b, nz.data(), qv(c.bogie_joint, false),
                                qv(c.steer_joint, false), qv(c.bogie_joint, true), qv(c.steer_joint, true), in, out);
      y(w) = out[0] + nz(3 + w);
      y(nw + w) = out[1] + nz(3 + nw + 2 * nq + w);
      y(2 * nw + w) = out[2] + nz(3 + 2 * nw + 2 * nq + w);
    }
    return y;
  };
  auto h_linear = [&](const Eigen::VectorXd& x, const Inputs& in) {
    using J = ceres::Jet<double, 13>;  // v(3) s gamma beta n_w(3) q_b q_s qd_b qd_s
    Linearized r;
    r.value = Eigen::VectorXd(ny);
    r.dx = Eigen::MatrixXd::Zero(ny, nx);
    r.dn = Eigen::MatrixXd::Zero(ny, nm);
    for (int w = 0; w < nw; ++w) {
      const auto& c = m.wheels[static_cast<std::size_t>(w)];
      J v[3], nw3[3];
      for (int k = 0; k < 3; ++k) {
        v[k] = J(x(3 + k), k);
        nw3[k] = J(0.0, 6 + k);
      }
      const J s(x(6 + w), 3), g(L.na >= 6 ? x(12 + w) : 0.0, 4), b(L.na >= 12 ? x(18 + w) : 0.0, 5);
      auto qv = [&](int j, bool rate, int slot) {
        return j < 0 ? J(0.0) : J((rate ? in.qdot : in.q)[static_cast<std::size_t>(j)], slot);
      };
      J out[3];
      wheel_measurement<J>(m, w, frame, v, s, g, b, nw3, qv(c.bogie_joint, false, 9), qv(c.steer_joint, false, 10),
                           qv(c.bogie_joint, true, 11), qv(c.steer_joint, true, 12), in, out);
      const int rows[3] = {w, nw + w, 2 * nw + w};
      for (int k = 0; k < 3; ++k) {
        const int row = rows[k];
        r.value(row) = out[k].a;
        for (int c3 = 0; c3 < 3; ++c3) {
          r.dx(row, 3 + c3) = out[k].v[c3];
          r.dn(row, c3) = out[k].v[6 + c3];
        }
        r.dx(row, 6 + w) = out[k].v[3];
        if (L.na >= 6) r.dx(row, 12 + w) = out[k].v[4];
        if (L.na >= 12) r.dx(row, 18 + w) = out[k].v[5];
        // Joint noise enters with a minus sign (Eq. 4.16: true = measured - noise).
        if (c.bogie_joint >= 0) {
          r.dn(row, 3 + nw + c.bogie_joint) = -out[k].v[9];
          r.dn(row, 3 + nw + nq + c.bogie_joint) = -out[k].v[11];
        }
        if (c.steer_joint >= 0) {
          r.dn(row, 3 + nw + c.steer_joint) = -out[k].v[10];
          r.dn(row, 3 + nw + nq + c.steer_joint) = -out[k].v[12];
        }
      }
      r.dn(w, 3 + w) = 1.0;
      r.dn(nw + w, 3 + nw + 2 * nq + w) = 1.0;
      r.dn(2 * nw + w, 3 + 2 * nw + 2 * nq + w) = 1.0;
    }
    return r;
  };

  // Initial state: levelled attitude, forward speed from the wheels, no slip, flat contact.
  Eigen::VectorXd x0 = Eigen::VectorXd::Zero(nx);
  x0(1) = pitch0;
  x0(2) = roll0;
  {
    const Inputs in = inputs_at(0);
    std::vector<double> r = in.wheel_rate;
    std::nth_element(r.begin(), r.begin() + 3, r.end());
    x0(3) = r[3] * m.wheel_radius;
  }
  Eigen::VectorXd p0(nx);
  p0.segment(0, 3).setConstant(1e-4);
  p0.segment(3, 3).setConstant(1e-4);
  p0.segment(6, 6).setConstant(1e-4);
  if (L.na > 0) p0.segment(12, L.na).setConstant(1e-3);
  ExtendedKalmanFilter ekf;
  UnscentedKalmanFilter ukf;
  ekf.x = ukf.x = x0;
  ekf.P = ukf.P = Eigen::MatrixXd(p0.asDiagonal());
  Eigen::VectorXd y_meas = Eigen::VectorXd::Zero(ny);

  // Outputs.
  std::vector<std::vector<double>> out(static_cast<std::size_t>(nx), std::vector<double>(n, NAN));
  std::vector<double> valid(n, 0.0);
  ContactAngleResult result;
  for (std::size_t i = 0; i < n; ++i) {
    const Inputs in = inputs_at(i);
    const double ts = i == 0 ? 0.0 : t[i] - t[i - 1];
    bool still = true;
    for (double w : in.wheel_rate) still = still && std::abs(w) < o.standstill_wheel_rate;
    still = still && in.gyro.norm() < o.standstill_gyro_rate;
    for (int w = 0; w < nw; ++w) y_meas(w) = in.wheel_rate[static_cast<std::size_t>(w)];
    Eigen::VectorXd x;
    if (o.filter == FilterKind::ekf) {
      if (i > 0) ekf.predict_diagonal(f_linear(ekf.x, in, ts), qdiag);
      if (!still) ekf.update_diagonal(h_linear(ekf.x, in), rdiag, y_meas);
      if (o.reset_cross_covariance) ekf.reset_cross_covariance();
      x = ekf.x;
    } else {
      const auto f = [&](const Eigen::VectorXd& xs, const Eigen::VectorXd& nz) { return f_double(xs, nz, in, ts); };
      const auto hh = [&](const Eigen::VectorXd& xs, const Eigen::VectorXd& nz) { return h_double(xs, nz, in); };
      if (i > 0 && !still) {
        ukf.step(f, Q, hh, R_used, y_meas);
      } else if (i > 0) {  // predict only: the state's mean through f with zero noise
        ukf.x = f(ukf.x, Eigen::VectorXd::Zero(np));
      }
      if (o.reset_cross_covariance) ukf.reset_cross_covariance();
      x = ukf.x;
    }
    if (!x.allFinite()) throw DataError("the filter diverged at t = " + std::to_string(t[i]) + " s");
    for (int k = 0; k < nx; ++k) out[static_cast<std::size_t>(k)][i] = x(k);
    valid[i] = still ? 0.0 : 1.0;
    result.standstill_samples += still;
    if (o.progress && i % 2000 == 0) o.progress(static_cast<double>(i) / static_cast<double>(n));
  }
  {
    const Eigen::MatrixXd& P = o.filter == FilterKind::ekf ? ekf.P : ukf.P;
    for (int a = 0; a < nx; ++a) {
      for (int b = 0; b < a; ++b) {
        const double r = std::abs(P(a, b)) / std::sqrt(P(a, a) * P(b, b));
        if (std::isfinite(r)) result.max_cross_correlation = std::max(result.max_cross_correlation, r);
      }
    }
  }

  // Streams; slip and angles are invalid (NaN) at standstill.
  result.estimates.metadata = lg.metadata;
  result.estimates.metadata.extra["estimator"] = "contact-angle (seed 000)";
  {
    log::Stream s("estimate/contact/body", t);
    s.add_channel("velocity_x", "m/s", out[3], "body frame g");
    s.add_channel("velocity_y", "m/s", out[4]);
    s.add_channel("velocity_z", "m/s", out[5]);
    s.add_channel("yaw", "rad", out[0]);
    s.add_channel("pitch", "rad", out[1]);
    s.add_channel("roll", "rad", out[2]);
    result.estimates.add_stream(std::move(s));
  }
  {
    log::Stream s("estimate/contact/wheels", t);
    auto masked = [&](const std::vector<double>& v) {
      std::vector<double> r = v;
      for (std::size_t i = 0; i < n; ++i) {
        if (valid[i] == 0.0) r[i] = NAN;
      }
      return r;
    };
    for (int w = 0; w < nw; ++w) s.add_channel("slip_" + m.wheels[static_cast<std::size_t>(w)].name, "1", masked(out[static_cast<std::size_t>(6 + w)]));
    for (int w = 0; w < nw && L.na >= 6; ++w) {
      s.add_channel("contact_angle_" + m.wheels[static_cast<std::size_t>(w)].name, "rad", masked(out[static_cast<std::size_t>(12 + w)]));
    }
    for (int w = 0; w < nw && L.na >= 12; ++w) {
      s.add_channel("side_slip_" + m.wheels[static_cast<std::size_t>(w)].name, "rad", masked(out[static_cast<std::size_t>(18 + w)]));
    }
    s.add_channel("valid", "bool", valid, "0 at standstill: slip and angles undefined, held");
    result.estimates.add_stream(std::move(s));
  }
  result.seconds = t.back() - t.front();

  // Errors against truth over the moving samples.
  const log::Stream* tb = lg.find_stream("truth/body");
  const log::Stream* tw = lg.find_stream("truth/wheels");
  if (tb != nullptr && tw != nullptr) {
    result.has_truth = true;
    StateErrors& e = result.rms;
    e.velocity.assign(3, 0.0);
    e.slip.assign(6, 0.0);
    e.contact_angle.assign(L.na >= 6 ? 6 : 0, 0.0);
    e.side_slip.assign(L.na >= 12 ? 6 : 0, 0.0);
    const char* vn[3] = {"velocity_x", "velocity_y", "velocity_z"};
    for (std::size_t i = 0; i < n; ++i) {
      if (valid[i] == 0.0) continue;
      const std::size_t k = tb->nearest_index(t[i]), kw = tw->nearest_index(t[i]);
      const double speed = std::hypot(tb->channel("velocity_x").values[k], tb->channel("velocity_y").values[k]);
      if (speed < 1e-3) continue;
      ++e.samples;
      for (int c = 0; c < 3; ++c) e.velocity[static_cast<std::size_t>(c)] += std::pow(out[static_cast<std::size_t>(3 + c)][i] - tb->channel(vn[c]).values[k], 2);
      for (int w = 0; w < nw; ++w) {
        const std::string& name = m.wheels[static_cast<std::size_t>(w)].name;
        e.slip[static_cast<std::size_t>(w)] += std::pow(out[static_cast<std::size_t>(6 + w)][i] - tw->channel("slip_" + name).values[kw], 2);
        if (L.na >= 6) e.contact_angle[static_cast<std::size_t>(w)] += std::pow(out[static_cast<std::size_t>(12 + w)][i] - tw->channel("contact_angle_" + name).values[kw], 2);
        if (L.na >= 12) e.side_slip[static_cast<std::size_t>(w)] += std::pow(out[static_cast<std::size_t>(18 + w)][i] - tw->channel("side_slip_" + name).values[kw], 2);
      }
    }
    const double c = static_cast<double>(std::max<std::size_t>(e.samples, 1));
    for (auto* v : {&e.velocity, &e.slip, &e.contact_angle, &e.side_slip}) {
      for (double& x : *v) x = std::sqrt(x / c);
    }
  }
  if (o.progress) o.progress(1.0);
  return result;
}

}  // namespace roverlab::estimation
