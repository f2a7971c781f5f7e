#include "core/estimation/contact_angle.h"

#include <ceres/jet.h>

#include <algorithm>
#include <cmath>

#include "core/common/error.h"
#include "core/estimation/contact_angle_model.h"
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

using contact::Inputs;
using contact::strapdown;

struct Layout {
  int na = 0;  // angle states per wheel set: 0, 6 or 12
  int nw = 6, nq = 9;
  int nx() const { return 12 + na; }
  int np() const { return nx() + 6; }  // n_att, n_v, n_s, n_gamma, n_beta, n_f, n_w
  int ny() const { return 3 * nw; }
  int nm() const { return 3 + nw + 2 * nq + 2 * nw; }  // n_w(gyro), n_wheel, n_q, n_qdot, n_vy, n_vz
};

// What the fast EKF needs of the model: noises in Layout order.
struct Setup {
  const kinematics::RoverModel* m = nullptr;
  kinematics::WheelFrame frame = kinematics::WheelFrame::contact;
  Eigen::Vector3d g_i = Eigen::Vector3d::Zero();
  double slip_decay = 0, angle_decay = 0;  // 1/s (Eq. 4.15, 5.3-5.6)
  Eigen::VectorXd q, r;                     // process and measurement noise variances
  int nq = 0;
};

// The EKF of Eq. 2.14-2.17 specialised to this model: fixed-size matrices,
// the process Jacobian's block structure (only the attitude-velocity block
// is full) and the measurement Jacobian's (each wheel sees the velocity and
// its own slip and angles), hand-derived wheel Jacobians. Tested equal to
// the generic ExtendedKalmanFilter with ceres::Jet Jacobians.
template <int NA>
class FastEkf {
 public:
  static constexpr int NX = 12 + NA, NY = 18, NR = NX - 6;
  Eigen::Matrix<double, NX, 1> x;
  Eigen::Matrix<double, NX, NX> P;

  // Eq. 2.14-2.15 with F = blockdiag(A, diag(d)): P11 <- A P11 A^T + G G^T,
  // P12 <- A P12 D, P22 <- D P22 D + Q22.
  void predict(const Setup& s, const Inputs& in, double ts) {
    // Jacobians of Eq. 4.13-4.14 with respect to attitude, velocity and the
    // accelerometer and gyro noises; n_att and n_v enter with identity.
    using Jt = ceres::Jet<double, 12>;
    const Jt zero(0.0);
    const Jt zeros[3] = {zero, zero, zero};
    Jt a[3], v[3], nf[3], nw[3], an[3], vn[3];
    for (int k = 0; k < 3; ++k) {
      a[k] = Jt(x(k), k);
      v[k] = Jt(x(3 + k), 3 + k);
      nf[k] = Jt(0.0, 6 + k);
      nw[k] = Jt(0.0, 9 + k);
    }
    strapdown<Jt>(a, v, zeros, zeros, nf, nw, in, s.g_i, ts, an, vn);
    Eigen::Matrix<double, 6, 6> A, G;  // G: noise Jacobian times the noise standard deviations
    for (int k = 0; k < 3; ++k) {
      x(k) = an[k].a;
      x(3 + k) = vn[k].a;
      for (int c = 0; c < 6; ++c) {
        A(k, c) = an[k].v[c];
        A(3 + k, c) = vn[k].v[c];
        const double sd = std::sqrt(s.q(NX + c));
        G(k, c) = an[k].v[6 + c] * sd;
        G(3 + k, c) = vn[k].v[6 + c] * sd;
      }
    }
    Eigen::Matrix<double, NR, 1> d;
    d.template head<6>().setConstant(1.0 - s.slip_decay * ts);
    d.template tail<NA>().setConstant(1.0 - s.angle_decay * ts);
    x.template tail<NR>() = d.cwiseProduct(x.template tail<NR>());
    const Eigen::Matrix<double, 6, 6> AP = A.lazyProduct(P.template topLeftCorner<6, 6>());
    Eigen::Matrix<double, 6, 6> P11 = AP.lazyProduct(A.transpose()) + G.lazyProduct(G.transpose());
    P11.diagonal() += s.q.template head<6>();
    const Eigen::Matrix<double, 6, NR> P12 = A.lazyProduct(P.template topRightCorner<6, NR>()) * d.asDiagonal();
    P.template topLeftCorner<6, 6>() = 0.5 * (P11 + P11.transpose());
    P.template topRightCorner<6, NR>() = P12;
    P.template bottomLeftCorner<NR, 6>() = P12.transpose();
    P.template bottomRightCorner<NR, NR>() = P.template bottomRightCorner<NR, NR>().cwiseProduct(d * d.transpose());
    P.template bottomRightCorner<NR, NR>().diagonal() += s.q.segment(6, NR);
  }

  // Eq. 2.16-2.17, Joseph form (I - KH) P (I - KH)^T + K R K^T expanded as
  // P - K H P - P H^T K^T + K S K^T with K S K^T = (K L)(K L)^T, S = L L^T.
  // diagonal_only keeps only P's diagonal (the seed's workaround follows).
  bool update(const Setup& s, const Inputs& in, bool diagonal_only, bool block_diagonal = false) {
    const kinematics::RoverModel& m = *s.m;
    contact::WheelLinearization lin[6];
    int priv[6][3];
    constexpr int npriv = 1 + NA / 6;
    Eigen::Matrix<double, NY, 1> innov;
    for (int w = 0; w < 6; ++w) {
      lin[w] = contact::linearize_wheel(m, w, s.frame, x.data() + 3, x(6 + w), NA >= 6 ? x(12 + w) : 0.0,
                                        NA >= 12 ? x(18 + w) : 0.0, in);
      innov.template segment<3>(3 * w) = Eigen::Vector3d(in.wheel_rate[w], 0.0, 0.0) - lin[w].value;
      for (int p = 0; p < 3; ++p) priv[w][p] = 6 + 6 * p + w;
    }
    // P H^T and H P H^T, one wheel (three rows of H) at a time.
    Eigen::Matrix<double, NX, NY> PHt;
    if (block_diagonal) {
      // After the seed's reset P = blockdiag(P11, diag): a private row of
      // P H^T holds its own wheel's three columns only.
      PHt.setZero();
      for (int w = 0; w < 6; ++w) {
        PHt.template block<6, 3>(0, 3 * w).noalias() =
            P.template block<6, 3>(0, 3) * lin[w].d.template leftCols<3>().transpose();
        for (int p = 0; p < npriv; ++p) {
          const int c = priv[w][p];
          PHt.template block<1, 3>(c, 3 * w) = P(c, c) * lin[w].d.col(3 + p).transpose();
        }
      }
    } else {
      for (int w = 0; w < 6; ++w) {
        auto cols = PHt.template middleCols<3>(3 * w);
        cols.noalias() = P.template middleCols<3>(3) * lin[w].d.template leftCols<3>().transpose();
        for (int p = 0; p < npriv; ++p) cols.noalias() += P.col(priv[w][p]) * lin[w].d.col(3 + p).transpose();
      }
    }
    Eigen::Matrix<double, NY, NY> S;
    for (int w = 0; w < 6; ++w) {
      auto rows = S.template middleRows<3>(3 * w);
      rows.noalias() = lin[w].d.template leftCols<3>() * PHt.template middleRows<3>(3);
      for (int p = 0; p < npriv; ++p) rows.noalias() += lin[w].d.col(3 + p) * PHt.row(priv[w][p]);
    }
    add_measurement_noise(s, lin, S);
    Eigen::Matrix<double, NY, NY> Lm;
    if (!cholesky(S, Lm)) return false;
    // W^T = P H^T L^-T and z = L^-1 (y - h) by forward substitution, so
    // that K = W^T L^-1 and K (y - h) = W^T z.
    Eigen::Matrix<double, NX, NY> Wt = PHt;
    Eigen::Matrix<double, NY, 1> z = innov;
    for (int r = 0; r < NY; ++r) {
      for (int c = 0; c < r; ++c) {
        Wt.col(r) -= Lm(r, c) * Wt.col(c);
        z(r) -= Lm(r, c) * z(c);
      }
      Wt.col(r) /= Lm(r, r);
      z(r) /= Lm(r, r);
    }
    x.noalias() += Wt * z;
    if (diagonal_only) {
      // The diagonal of the Joseph form with the optimal gain:
      // P_ii - (K H P)_ii - (P H^T K^T)_ii + (K S K^T)_ii = P_ii - |W_i|^2.
      const Eigen::Matrix<double, NX, 1> diag = P.diagonal() - Wt.rowwise().squaredNorm();
      if ((diag.array() > 0.0).all()) {
        P = diag.asDiagonal();
        return true;
      }
    }
    // K from K L = W^T (backward substitution), then the Joseph form.
    Eigen::Matrix<double, NX, NY> K = Wt;
    for (int c = NY - 1; c >= 0; --c) {
      for (int r = c + 1; r < NY; ++r) K.col(c) -= Lm(r, c) * K.col(r);
      K.col(c) /= Lm(c, c);
    }
    Eigen::Matrix<double, NX, NY> V = Eigen::Matrix<double, NX, NY>::Zero();  // K L
    for (int c = 0; c < NY; ++c) {
      for (int r = c; r < NY; ++r) V.col(c) += Lm(r, c) * K.col(r);
    }
    const Eigen::Matrix<double, NX, NX> T = K * PHt.transpose();
    P -= T + T.transpose();
    P.noalias() += V * V.transpose();
    if (diagonal_only) P = P.diagonal().asDiagonal();
    return true;
  }

 private:
  // S = L L^T for a small fixed-size S (Cholesky-Banachiewicz on L^T's
  // contiguous columns; Eigen's LLT goes through dynamic-size kernels here).
  // False when S is not positive definite.
  static bool cholesky(const Eigen::Matrix<double, NY, NY>& S, Eigen::Matrix<double, NY, NY>& L) {
    Eigen::Matrix<double, NY, NY> U = Eigen::Matrix<double, NY, NY>::Zero();  // L^T
    for (int i = 0; i < NY; ++i) {
      for (int j = 0; j < i; ++j) U(j, i) = (S(i, j) - U.col(i).head(j).dot(U.col(j).head(j))) / U(j, j);
      const double d = S(i, i) - U.col(i).head(i).squaredNorm();
      if (!(d > 0.0)) return false;
      U(i, i) = std::sqrt(d);
    }
    L = U.transpose();
    return true;
  }

  // S += M R M^T: wheel-rate, lateral and normal noises on their own rows;
  // the gyro noise couples every wheel, a joint's noise the wheels it carries.
  static void add_measurement_noise(const Setup& s, const contact::WheelLinearization* lin, Eigen::Matrix<double, NY, NY>& S) {
    const kinematics::RoverModel& m = *s.m;
    const int nw = 6, nq = s.nq;
    Eigen::Matrix3d Gw[6];
    const Eigen::Vector3d gyro_sd = s.r.head<3>().cwiseSqrt();
    for (int w = 0; w < nw; ++w) {
      Gw[w] = lin[w].d.template block<3, 3>(0, 6) * gyro_sd.asDiagonal();
      S(3 * w, 3 * w) += s.r(3 + w);
      S(3 * w + 1, 3 * w + 1) += s.r(3 + nw + 2 * nq + w);
      S(3 * w + 2, 3 * w + 2) += s.r(3 + 2 * nw + 2 * nq + w);
    }
    for (int w1 = 0; w1 < nw; ++w1) {
      const auto& c1 = m.wheels[static_cast<std::size_t>(w1)];
      const int j1[2] = {c1.bogie_joint, c1.steer_joint};
      for (int w2 = 0; w2 <= w1; ++w2) {
        const auto& c2 = m.wheels[static_cast<std::size_t>(w2)];
        const int j2[2] = {c2.bogie_joint, c2.steer_joint};
        Eigen::Matrix3d B = Gw[w1] * Gw[w2].transpose();
        for (int a = 0; a < 2; ++a) {
          for (int b = 0; b < 2; ++b) {
            if (j1[a] < 0 || j1[a] != j2[b]) continue;
            const int j = j1[a];
            B.noalias() += s.r(3 + nw + j) * lin[w1].d.col(9 + a) * lin[w2].d.col(9 + b).transpose();
            B.noalias() += s.r(3 + nw + nq + j) * lin[w1].d.col(11 + a) * lin[w2].d.col(11 + b).transpose();
          }
        }
        S.template block<3, 3>(3 * w1, 3 * w2) += B;
        if (w2 != w1) S.template block<3, 3>(3 * w2, 3 * w1) += B.transpose();
      }
    }
  }
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

  auto inputs_at = [&](std::size_t i) {
    Inputs in;
    in.gyro = Eigen::Vector3d((*imu_ch[0])[i], (*imu_ch[1])[i], (*imu_ch[2])[i]);
    in.accel = Eigen::Vector3d((*imu_ch[3])[i], (*imu_ch[4])[i], (*imu_ch[5])[i]);
    const std::size_t kj = std::min(joints.nearest_index(t[i]), joints.size() - 1);
    const std::size_t kw = std::min(wheels.nearest_index(t[i]), wheels.size() - 1);
    for (int j = 0; j < nq; ++j) {
      in.q[j] = (*q_ch[static_cast<std::size_t>(j)])[kj];
      in.qdot[j] = fused_rate.empty() ? (*qd_ch[static_cast<std::size_t>(j)])[kj] : fused_rate[static_cast<std::size_t>(j)][kj];
      if (!std::isfinite(in.q[j])) throw DataError("stream 'joints': missing sample at t = " + std::to_string(t[i]) + " s");
    }
    for (int w = 0; w < nw; ++w) in.wheel_rate[w] = (*w_ch[static_cast<std::size_t>(w)])[kw];
    if (!std::isfinite(in.gyro.sum() + in.accel.sum())) {
      throw DataError("stream 'imu': missing sample at t = " + std::to_string(t[i]) + " s");
    }
    return in;
  };

  const double angle_keep = o.angle_model == AngleModel::damped ? 1.0 : 0.0;  // multiplies -A ts
  // Process model in double (UKF) and linearised with Jets (EKF).
  double trig_att[3] = {NAN, NAN, NAN};  // the attitude whose cosines and sines are in trig
  contact::AttitudeTrig<double> trig{};
  auto f_double = [&](const Eigen::VectorXd& x, const Eigen::VectorXd& nz, const Inputs& in, double ts, Eigen::VectorXd& y) {
    y.resize(nx);
    if (!std::equal(trig_att, trig_att + 3, x.data())) {  // sigma points mostly share the attitude
      std::copy(x.data(), x.data() + 3, trig_att);
      trig = contact::attitude_trig<double>(x.data());
    }
    strapdown<double>(x.data(), trig, x.data() + 3, nz.data(), nz.data() + 3, nz.data() + nx, nz.data() + nx + 3, in, g_i,
                      ts, y.data(), y.data() + 3);
    for (int k = 0; k < 6; ++k) y(6 + k) = x(6 + k) * (1.0 - o.slip_damping * ts) + nz(6 + k);  // Eq. 4.15
    for (int k = 0; k < L.na; ++k) {
      y(12 + k) = x(12 + k) * (1.0 - angle_keep * o.angle_damping * ts) + nz(12 + k);  // Eq. 5.3-5.6
    }
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
    f_double(x, Eigen::VectorXd::Zero(np), in, ts, r.value);
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
  // The UKF's measurement model at a sigma point, from each wheel's geometry
  // at the measured joint angles (recomputed only for a sigma point that
  // moves one of its joints) and its final rotation (kept while gamma and
  // beta repeat).
  struct RotationMemo {
    double gamma = NAN, beta = NAN, cg = 1.0, sg = 0.0, cb = 1.0, sb = 0.0;
    Eigen::Matrix3d C;
  };
  contact::WheelGeometry geo0[6];
  RotationMemo memo[6][2];
  std::vector<std::vector<int>> wheels_of_joint(static_cast<std::size_t>(nq));
  for (int w = 0; w < nw; ++w) {
    const auto& c = m.wheels[static_cast<std::size_t>(w)];
    for (int j : {c.bogie_joint, c.steer_joint}) {
      if (j >= 0) wheels_of_joint[static_cast<std::size_t>(j)].push_back(w);
    }
  }
  // Its noise order puts the additive noises last, in the measurement's
  // order: n_w (gyro 3), n_q, n_qdot, then n_wheel (6), n_vy (6), n_vz (6).
  Eigen::VectorXd r_ukf(nm);
  r_ukf << rdiag.head(3), rdiag.segment(3 + nw, 2 * nq), rdiag.segment(3, nw), rdiag.segment(3 + nw + 2 * nq, 2 * nw);
  const Eigen::MatrixXd R_ukf = r_ukf.asDiagonal();
  // One wheel's three rows of h.
  auto h_wheel = [&](int w, const Eigen::VectorXd& x, const Eigen::VectorXd& nz, const Inputs& in, Eigen::VectorXd& y) {
    const Eigen::Vector3d omega = in.gyro - nz.head<3>();
    const double* nzq = nz.data() + 3;        // joint-angle noises
    const double* nzqd = nz.data() + 3 + nq;  // joint-rate noises
    double qd[contact::kMaxJoints], qn[contact::kMaxJoints];
    const contact::WheelGeometry* g = &geo0[w];
    contact::WheelGeometry moved;
    for (int k = 0; k < g->nj; ++k) {
      const int j = g->joint[k];
      qd[j] = in.qdot[j] - nzqd[j];
      if (nzq[j] != 0.0 && g == &geo0[w]) {
        for (int i = 0; i < nq; ++i) qn[i] = in.q[i] - nzq[i];
        moved = contact::wheel_geometry(m, w, qn);
        g = &moved;
      }
    }
    const double gamma = L.na >= 6 ? x(12 + w) : 0.0, beta = L.na >= 12 ? x(18 + w) : 0.0;
    RotationMemo* hit = nullptr;
    for (auto& e : memo[w]) {
      if (e.gamma == gamma && e.beta == beta) hit = &e;
    }
    if (hit == nullptr) {  // a sigma point usually moves one of the two angles: keep the other's cos/sin
      const RotationMemo& first = memo[w][0];
      hit = std::isnan(first.gamma) ? &memo[w][0] : &memo[w][1];
      if (first.gamma == gamma) {
        hit->cg = first.cg;
        hit->sg = first.sg;
      } else {
        hit->cg = std::cos(gamma);
        hit->sg = std::sin(gamma);
      }
      if (first.beta == beta) {
        hit->cb = first.cb;
        hit->sb = first.sb;
      } else {
        hit->cb = std::cos(beta);
        hit->sb = std::sin(beta);
      }
      hit->gamma = gamma;
      hit->beta = beta;
      hit->C = contact::final_rotation(frame, hit->cg, hit->sg, hit->cb, hit->sb);
    }
    const Eigen::Vector3d u = contact::wheel_measurement(*g, hit->C, frame, m.wheel_radius, x.data() + 3, x(6 + w),
                                                         hit->cb, omega, qd);
    for (int k = 0; k < 3; ++k) y(k * nw + w) = u(k) + nz(3 + 2 * nq + k * nw + w);
  };
  auto h_ukf = [&](const Eigen::VectorXd& x, const Eigen::VectorXd& nz, const Inputs& in, Eigen::VectorXd& y) {
    y.resize(ny);
    for (int w = 0; w < nw; ++w) h_wheel(w, x, nz, in, y);
  };
  // The same at a sigma point that moves only the listed entries: wheels
  // they do not reach keep the centre's rows. Velocity and gyro reach every
  // wheel, attitude none, a slip or angle its wheel, a joint its wheels.
  auto h_ukf_incremental = [&](const Eigen::VectorXd& x, const Eigen::VectorXd& nz,
                               const std::vector<Eigen::Index>& changed_x, const std::vector<Eigen::Index>& changed_n,
                               const Eigen::VectorXd& y0, const Inputs& in, Eigen::VectorXd& y) {
    bool reach[6] = {false, false, false, false, false, false};
    bool all = false;
    for (Eigen::Index i : changed_x) {
      if (i >= 3 && i < 6) all = true;
      if (i >= 6) reach[(i - 6) % 6] = true;
    }
    for (Eigen::Index i : changed_n) {
      if (i < 3 || i >= 3 + 2 * nq) {
        all = true;
      } else {
        for (int w : wheels_of_joint[static_cast<std::size_t>((i - 3) % nq)]) reach[w] = true;
      }
    }
    y = y0;
    for (int w = 0; w < nw; ++w) {
      if (all || reach[w]) h_wheel(w, x, nz, in, y);
    }
  };
  // The generic EKF's measurement model (the fast EKF's reference), with
  // each wheel linearised by ceres::Jet. Noise order: n_w (gyro 3),
  // n_wheel (6), n_q, n_qdot, n_vy (6), n_vz (6).
  auto h_linear = [&](const Eigen::VectorXd& x, const Inputs& in) {
    Linearized r;
    r.value = Eigen::VectorXd(ny);
    r.dx = Eigen::MatrixXd::Zero(ny, nx);
    r.dn = Eigen::MatrixXd::Zero(ny, nm);
    for (int w = 0; w < nw; ++w) {
      const auto& c = m.wheels[static_cast<std::size_t>(w)];
      const contact::WheelLinearization lin = contact::linearize_wheel_autodiff(
          m, w, frame, x.data() + 3, x(6 + w), L.na >= 6 ? x(12 + w) : 0.0, L.na >= 12 ? x(18 + w) : 0.0, in);
      for (int k = 0; k < 3; ++k) {
        const int row = k * nw + w;
        r.value(row) = lin.value(k);
        r.dx.block<1, 3>(row, 3) = lin.d.block<1, 3>(k, 0);
        r.dn.block<1, 3>(row, 0) = lin.d.block<1, 3>(k, 6);
        r.dx(row, 6 + w) = lin.d(k, 3);
        if (L.na >= 6) r.dx(row, 12 + w) = lin.d(k, 4);
        if (L.na >= 12) r.dx(row, 18 + w) = lin.d(k, 5);
        // Joint noise enters with a minus sign (Eq. 4.16: true = measured - noise).
        if (c.bogie_joint >= 0) {
          r.dn(row, 3 + nw + c.bogie_joint) = -lin.d(k, 9);
          r.dn(row, 3 + nw + nq + c.bogie_joint) = -lin.d(k, 11);
        }
        if (c.steer_joint >= 0) {
          r.dn(row, 3 + nw + c.steer_joint) = -lin.d(k, 10);
          r.dn(row, 3 + nw + nq + c.steer_joint) = -lin.d(k, 12);
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
    std::vector<double> r(in.wheel_rate, in.wheel_rate + 6);
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
  ukf.additive_process_noise = ukf.additive_measurement_noise = !o.reference_ukf;  // Eq. 4.15-4.17, 4.20
  ukf.diagonal_only = o.reset_cross_covariance && !o.reference_ukf;
  const Inputs* ukf_inputs = nullptr;  // this step's inputs, for the incremental h
  if (!o.reference_ukf) {
    ukf.h_incremental = [&](const Eigen::VectorXd& xs, const Eigen::VectorXd& nz, const std::vector<Eigen::Index>& cx,
                            const std::vector<Eigen::Index>& cn, const Eigen::VectorXd& y0, Eigen::VectorXd& out_y) {
      h_ukf_incremental(xs, nz, cx, cn, y0, *ukf_inputs, out_y);
    };
  }
  ekf.x = ukf.x = x0;
  ekf.P = ukf.P = Eigen::MatrixXd(p0.asDiagonal());
  Eigen::VectorXd y_meas = Eigen::VectorXd::Zero(ny);

  Setup setup;
  setup.m = &m;
  setup.frame = frame;
  setup.g_i = g_i;
  setup.slip_decay = o.slip_damping;
  setup.angle_decay = angle_keep * o.angle_damping;
  setup.q = qdiag;
  setup.r = rdiag;
  setup.nq = nq;
  FastEkf<0> fast0;
  FastEkf<6> fast6;
  FastEkf<12> fast12;

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
    if (o.filter == FilterKind::ekf && !o.reference_ekf) {
      const auto step = [&](auto& fe) {
        if (i == 0) {
          fe.x = x0;
          fe.P = p0.asDiagonal();
        }
        if (i > 0) fe.predict(setup, in, ts);
        // With the reset, P is blockdiag(P11, diag) after the predict.
        if (!still) fe.update(setup, in, o.reset_cross_covariance, o.reset_cross_covariance);
        if (still && o.reset_cross_covariance) fe.P = fe.P.diagonal().asDiagonal();
        x = fe.x;
      };
      if (L.na == 0) step(fast0);
      if (L.na == 6) step(fast6);
      if (L.na == 12) step(fast12);
    } else if (o.filter == FilterKind::ekf) {
      if (i > 0) ekf.predict_diagonal(f_linear(ekf.x, in, ts), qdiag);
      if (!still) ekf.update_diagonal(h_linear(ekf.x, in), rdiag, y_meas);
      if (o.reset_cross_covariance) ekf.reset_cross_covariance();
      x = ekf.x;
    } else {
      const auto f = [&](const Eigen::VectorXd& xs, const Eigen::VectorXd& nz, Eigen::VectorXd& out_x) {
        f_double(xs, nz, in, ts, out_x);
      };
      const auto hh = [&](const Eigen::VectorXd& xs, const Eigen::VectorXd& nz, Eigen::VectorXd& out_y) {
        h_ukf(xs, nz, in, out_y);
      };
      ukf_inputs = &in;
      for (int w = 0; w < nw; ++w) {
        geo0[w] = contact::wheel_geometry(m, w, in.q);
        memo[w][0].gamma = memo[w][1].gamma = NAN;
      }
      if (i > 0 && !still) {
        ukf.step(f, Q, hh, R_ukf, y_meas);
      } else if (i > 0) {  // predict only: the state's mean through f with zero noise
        Eigen::VectorXd next;
        f(ukf.x, Eigen::VectorXd::Zero(np), next);
        ukf.x = next;
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
    Eigen::MatrixXd P = o.filter == FilterKind::ekf ? ekf.P : ukf.P;
    if (o.filter == FilterKind::ekf && !o.reference_ekf) {
      P = L.na == 0 ? Eigen::MatrixXd(fast0.P) : L.na == 6 ? Eigen::MatrixXd(fast6.P) : Eigen::MatrixXd(fast12.P);
    }
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
    const std::vector<double>* tv[3] = {&tb->channel("velocity_x").values, &tb->channel("velocity_y").values,
                                        &tb->channel("velocity_z").values};
    std::vector<const std::vector<double>*> ts_, tg_, tbeta_;
    for (const auto& wc : m.wheels) {
      ts_.push_back(&tw->channel("slip_" + wc.name).values);
      if (L.na >= 6) tg_.push_back(&tw->channel("contact_angle_" + wc.name).values);
      if (L.na >= 12) tbeta_.push_back(&tw->channel("side_slip_" + wc.name).values);
    }
    for (std::size_t i = 0; i < n; ++i) {
      if (valid[i] == 0.0) continue;
      const std::size_t k = tb->nearest_index(t[i]), kw = tw->nearest_index(t[i]);
      const double speed = std::hypot((*tv[0])[k], (*tv[1])[k]);
      if (speed < 1e-3) continue;
      ++e.samples;
      for (int c = 0; c < 3; ++c) e.velocity[static_cast<std::size_t>(c)] += std::pow(out[static_cast<std::size_t>(3 + c)][i] - (*tv[c])[k], 2);
      for (std::size_t w = 0; w < 6; ++w) {
        e.slip[w] += std::pow(out[6 + w][i] - (*ts_[w])[kw], 2);
        if (L.na >= 6) e.contact_angle[w] += std::pow(out[12 + w][i] - (*tg_[w])[kw], 2);
        if (L.na >= 12) e.side_slip[w] += std::pow(out[18 + w][i] - (*tbeta_[w])[kw], 2);
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
