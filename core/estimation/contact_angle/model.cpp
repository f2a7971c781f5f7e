#include "core/estimation/contact_angle/model.h"

#include <ceres/jet.h>

#include <algorithm>
#include <cmath>

namespace roverlab::estimation::contact {

WheelLinearization linearize_wheel_autodiff(const kinematics::RoverModel& m, int wheel, kinematics::WheelFrame frame,
                                            const double* v, double slip, double gamma, double beta, const Inputs& in) {
  using J = ceres::Jet<double, 13>;
  const auto& c = m.wheels[static_cast<std::size_t>(wheel)];
  J vj[3], nw[3];
  for (int k = 0; k < 3; ++k) {
    vj[k] = J(v[k], k);
    nw[k] = J(0.0, 6 + k);
  }
  const J s(slip, 3), g(gamma, 4), b(beta, 5);
  auto joint = [&](int j, bool rate, int slot) { return j < 0 ? J(0.0) : J((rate ? in.qdot : in.q)[j], slot); };
  J out[3];
  wheel_measurement<J>(m, wheel, frame, vj, s, g, b, nw, joint(c.bogie_joint, false, 9),
                       joint(c.steer_joint, false, 10), joint(c.bogie_joint, true, 11), joint(c.steer_joint, true, 12),
                       in, out);
  WheelLinearization r;
  for (int k = 0; k < 3; ++k) {
    r.value(k) = out[k].a;
    r.d.row(k) = out[k].v.transpose();
  }
  return r;
}

WheelGeometry wheel_geometry(const kinematics::RoverModel& m, int wheel, const double* q) {
  const kinematics::WheelChain& c = m.wheels[static_cast<std::size_t>(wheel)];
  WheelGeometry g;
  Eigen::Matrix4d X = Eigen::Matrix4d::Identity();
  for (int li : c.links) {
    const kinematics::DhLink& l = m.links[static_cast<std::size_t>(li)];
    double ct = l.cos_theta, st = l.sin_theta;
    if (l.joint >= 0) {
      const double theta = l.theta + q[l.joint];
      ct = std::cos(theta);
      st = std::sin(theta);
      if (g.nj < 2) {
        g.z[g.nj] = X.block<3, 1>(0, 2);
        g.o[g.nj] = X.block<3, 1>(0, 3);
        g.joint[g.nj] = l.joint;
        ++g.nj;
      }
    }
    kinematics::append_dh(X, ct, st, l.d, l.a, l.cos_alpha, l.sin_alpha);  // Eq. 2.8
  }
  g.Rd = X.block<3, 3>(0, 0);
  g.r = X.block<3, 1>(0, 3);
  for (int k = 0; k < 2; ++k) g.J[k] = k < g.nj ? Eigen::Vector3d(g.z[k].cross(g.r - g.o[k])) : Eigen::Vector3d::Zero();
  return g;
}

Eigen::Matrix3d final_rotation(kinematics::WheelFrame frame, double gamma, double beta) {
  return final_rotation(frame, std::cos(gamma), std::sin(gamma), std::cos(beta), std::sin(beta));
}

Eigen::Matrix3d final_rotation(kinematics::WheelFrame frame, double cg, double sg, double cb, double sb) {
  if (frame == kinematics::WheelFrame::drive) return Eigen::Matrix3d::Identity();
  Eigen::Matrix3d C;  // Rz(-gamma) Rx(pi/2)
  C << cg, 0, -sg, -sg, 0, -cg, 0, 1, 0;
  if (frame == kinematics::WheelFrame::side_slip) {
    Eigen::Matrix3d Rb;
    Rb << cb, -sb, 0, sb, cb, 0, 0, 0, 1;
    C = C * Rb;
  }
  return C;
}

WheelLinearization linearize_wheel(const kinematics::RoverModel& m, int wheel, kinematics::WheelFrame frame,
                                   const double* v, double slip, double gamma, double beta, const Inputs& in) {
  // The drive frame's pose and the axes and origins of the chain's joints
  // (first the bogie's, then the steering's), all in g.
  const WheelGeometry geo = wheel_geometry(m, wheel, in.q);
  const Eigen::Matrix3d& Rd = geo.Rd;
  const Eigen::Vector3d& r = geo.r;
  const int nj = geo.nj;
  const Eigen::Vector3d* z = geo.z;
  const Eigen::Vector3d* Jq = geo.J;
  double qd[2] = {0.0, 0.0};
  for (int k = 0; k < nj; ++k) qd[k] = in.qdot[geo.joint[k]];
  const Eigen::Vector3d omega = in.gyro;
  const Eigen::Vector3d vel(v[0], v[1], v[2]);
  // Eq. 4.8: the wheel's velocity in g.
  const Eigen::Vector3d w = vel + omega.cross(r) + Jq[0] * qd[0] + Jq[1] * qd[1];
  // Its derivative with respect to each joint angle: r moves by J_k, and
  // J_a by z_min(a,k) x J_max(a,k) (the later joint's column is carried by
  // the earlier joint's rotation).
  Eigen::Vector3d dw[2] = {Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()};
  for (int k = 0; k < nj; ++k) {
    dw[k] = omega.cross(Jq[k]);
    for (int a = 0; a < nj; ++a) dw[k] += z[std::min(a, k)].cross(Jq[std::max(a, k)]) * qd[a];
  }
  // Table 5.2: the contact frame is the drive frame turned by -gamma about
  // its axle then by pi/2 about x, C = Rz(-gamma) Rx(pi/2); the side-slip
  // frame turns by beta more, C Rz(beta). In closed form, with derivatives.
  Eigen::Matrix3d C = Eigen::Matrix3d::Identity(), dC_dg = Eigen::Matrix3d::Zero(), dC_db = Eigen::Matrix3d::Zero();
  const bool ss = frame == kinematics::WheelFrame::side_slip;
  const double cb = ss ? std::cos(beta) : 1.0, sb = ss ? std::sin(beta) : 0.0;  // one sincos
  if (frame != kinematics::WheelFrame::drive) {
    const double cg = std::cos(gamma), sg = std::sin(gamma);
    C << cg * cb, -cg * sb, -sg, -sg * cb, sg * sb, -cg, sb, cb, 0;
    dC_dg << -sg * cb, sg * sb, -cg, -cg * cb, cg * sb, sg, 0, 0, 0;
    if (ss) dC_db << -cg * sb, -cg * cb, 0, sg * sb, sg * cb, 0, cb, -sb, 0;
  }
  const Eigen::Matrix3d Rt = (Rd * C).transpose();
  const Eigen::Vector3d wd = Rd.transpose() * w;
  const Eigen::Vector3d u = C.transpose() * wd;
  WheelLinearization out;
  Eigen::Matrix<double, 3, 13>& D = out.d;
  D.setZero();
  D.leftCols<3>() = Rt;
  D.col(4) = dC_dg.transpose() * wd;
  D.col(5) = dC_db.transpose() * wd;
  // d(omega x r)/d(gyro noise) = [r]x since omega = gyro - noise: row k of R^T [r]x is (R^T)_k x r.
  for (int k = 0; k < 3; ++k) D.block<1, 3>(k, 6) = Rt.row(k).cross(r.transpose());
  for (int k = 0; k < nj; ++k) {
    D.col(9 + k) = Rt * (dw[k] - z[k].cross(w));  // d(R^T w) = R^T (dw - z_k x w)
    D.col(11 + k) = Rt * Jq[k];
  }
  // Eq. 4.20 / Table 5.1: rate = (cos beta) u_x / ((1 - s) r), then u_y, u_z.
  const double den = (1.0 - slip) * m.wheel_radius, sc = cb;
  out.value = Eigen::Vector3d(sc * u.x() / den, u.y(), u.z());
  D.row(0) *= sc / den;
  D(0, 3) = sc * u.x() / ((1.0 - slip) * den);
  if (ss) D(0, 5) -= sb * u.x() / den;
  return out;
}

ContactProcessModel::ContactProcessModel(ContactLayout layout, const Eigen::Vector3d& g_i, double slip_decay,
                                         double angle_decay)
    : layout_(layout), g_i_(g_i), slip_decay_(slip_decay), angle_decay_(angle_decay) {}

void ContactProcessModel::evaluate(const Eigen::VectorXd& x, const Eigen::VectorXd& nz, const Inputs& in, double ts,
                                   Eigen::VectorXd& y) const {
  const int nx = layout_.nx();
  y.resize(nx);
  if (!std::equal(trig_att_, trig_att_ + 3, x.data())) {  // sigma points mostly share the attitude
    std::copy(x.data(), x.data() + 3, trig_att_);
    trig_ = attitude_trig<double>(x.data());
  }
  strapdown<double>(x.data(), trig_, x.data() + 3, nz.data(), nz.data() + 3, nz.data() + nx, nz.data() + nx + 3, in,
                    g_i_, ts, y.data(), y.data() + 3);
  for (int k = 0; k < 6; ++k)
    y(ContactLayout::slip(k)) = x(ContactLayout::slip(k)) * slip_keep(ts) + nz(ContactLayout::slip(k));  // Eq. 4.15
  for (int k = 0; k < layout_.na; ++k)
    y(ContactLayout::kContactAngle + k) =
        x(ContactLayout::kContactAngle + k) * angle_keep(ts) + nz(ContactLayout::kContactAngle + k);  // Eq. 5.3-5.6
}

Linearized ContactProcessModel::linearize(const Eigen::VectorXd& x, const Inputs& in, double ts) const {
  const int nx = layout_.nx(), np = layout_.np();
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
  strapdown<J>(a, v, na, nv, nf, nw3, in, g_i_, ts, an, vn);
  Linearized r;
  evaluate(x, Eigen::VectorXd::Zero(np), in, ts, r.value);
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
    r.dx(ContactLayout::slip(k), ContactLayout::slip(k)) = slip_keep(ts);
    r.dn(ContactLayout::slip(k), ContactLayout::slip(k)) = 1.0;
  }
  for (int k = 0; k < layout_.na; ++k) {
    r.dx(ContactLayout::kContactAngle + k, ContactLayout::kContactAngle + k) = angle_keep(ts);
    r.dn(ContactLayout::kContactAngle + k, ContactLayout::kContactAngle + k) = 1.0;
  }
  return r;
}

WheelMeasurementModel::WheelMeasurementModel(const kinematics::RoverModel& m, kinematics::WheelFrame frame,
                                             ContactLayout layout)
    : m_(&m), frame_(frame), layout_(layout), wheels_of_joint_(static_cast<std::size_t>(layout.nq)) {
  for (int w = 0; w < layout_.nw; ++w) {
    const auto& c = m.wheels[static_cast<std::size_t>(w)];
    for (int j : {c.bogie_joint, c.steer_joint}) {
      if (j >= 0) wheels_of_joint_[static_cast<std::size_t>(j)].push_back(w);
    }
  }
}

Linearized WheelMeasurementModel::linearize(const Eigen::VectorXd& x, const Inputs& in) const {
  const kinematics::RoverModel& m = *m_;
  const int nx = layout_.nx(), ny = layout_.ny(), nm = layout_.nm(), nw = layout_.nw, nq = layout_.nq, na = layout_.na;
  Linearized r;
  r.value = Eigen::VectorXd(ny);
  r.dx = Eigen::MatrixXd::Zero(ny, nx);
  r.dn = Eigen::MatrixXd::Zero(ny, nm);
  for (int w = 0; w < nw; ++w) {
    const auto& c = m.wheels[static_cast<std::size_t>(w)];
    const WheelLinearization lin = linearize_wheel_autodiff(m, w, frame_, x.data() + 3, x(ContactLayout::slip(w)),
                                                            na >= 6 ? x(ContactLayout::contact_angle(w)) : 0.0,
                                                            na >= 12 ? x(ContactLayout::side_slip_angle(w)) : 0.0, in);
    for (int k = 0; k < 3; ++k) {
      const int row = k * nw + w;
      r.value(row) = lin.value(k);
      r.dx.block<1, 3>(row, 3) = lin.d.block<1, 3>(k, 0);
      r.dn.block<1, 3>(row, 0) = lin.d.block<1, 3>(k, 6);
      r.dx(row, ContactLayout::slip(w)) = lin.d(k, 3);
      if (na >= 6) r.dx(row, ContactLayout::contact_angle(w)) = lin.d(k, 4);
      if (na >= 12) r.dx(row, ContactLayout::side_slip_angle(w)) = lin.d(k, 5);
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
}

Eigen::VectorXd WheelMeasurementModel::ukf_noise_order(const Eigen::VectorXd& r) const {
  const int nw = layout_.nw, nq = layout_.nq;
  Eigen::VectorXd out(layout_.nm());
  out << r.head(3), r.segment(3 + nw, 2 * nq), r.segment(3, nw), r.segment(3 + nw + 2 * nq, 2 * nw);
  return out;
}

void WheelMeasurementModel::set_inputs(const Inputs& in) {
  in_ = in;
  for (int w = 0; w < layout_.nw; ++w) {
    geometry_[w] = wheel_geometry(*m_, w, in.q);
    const WheelGeometry& g = geometry_[w];
    joint_velocity_[w].setZero();
    for (int k = 0; k < g.nj; ++k) joint_velocity_[w] += g.J[k] * in.qdot[g.joint[k]];
    memo_[w][0].gamma = memo_[w][1].gamma = NAN;
  }
}

const WheelMeasurementModel::RotationMemo& WheelMeasurementModel::rotation(int w, double gamma, double beta) {
  RotationMemo* hit = nullptr;
  for (auto& e : memo_[w]) {
    if (e.gamma == gamma && e.beta == beta) hit = &e;
  }
  if (hit != nullptr) return *hit;
  // A sigma point usually moves one of the two angles: keep the other's cos/sin.
  const RotationMemo& first = memo_[w][0];
  hit = std::isnan(first.gamma) ? &memo_[w][0] : &memo_[w][1];
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
  hit->C = final_rotation(frame_, hit->cg, hit->sg, hit->cb, hit->sb);
  hit->T.noalias() = (geometry_[w].Rd * hit->C).transpose();
  return *hit;
}

// One wheel's three rows of h, from its geometry at the measured joint
// angles (recomputed only for a sigma point that moves one of its joints)
// and its final rotation (kept while gamma and beta repeat), with the
// joints' share of the wheel velocity at the measured rates kept too.
void WheelMeasurementModel::evaluate_wheel(int w, const Eigen::VectorXd& x, const Eigen::VectorXd& nz,
                                           Eigen::VectorXd& y) {
  const int nw = layout_.nw, nq = layout_.nq, na = layout_.na;
  const Inputs& in = in_;
  const Eigen::Vector3d omega = in.gyro - nz.head<3>();
  const double* nzq = nz.data() + 3;        // joint-angle noises
  const double* nzqd = nz.data() + 3 + nq;  // joint-rate noises
  const WheelGeometry& g = geometry_[w];
  bool moved = false, rate_noise = false;
  for (int k = 0; k < g.nj; ++k) {
    moved = moved || nzq[g.joint[k]] != 0.0;
    rate_noise = rate_noise || nzqd[g.joint[k]] != 0.0;
  }
  const double gamma = na >= 6 ? x(ContactLayout::contact_angle(w)) : 0.0,
               beta = na >= 12 ? x(ContactLayout::side_slip_angle(w)) : 0.0;
  const RotationMemo& rot = rotation(w, gamma, beta);
  Eigen::Vector3d u;
  if (!moved) {  // wheel_measurement at the measured joint angles, (R_d C)^T kept: Eq. 4.8, 4.20 / Table 5.1
    Eigen::Vector3d wv = x.segment<3>(3) + omega.cross(g.r);
    if (rate_noise) {
      for (int k = 0; k < g.nj; ++k) wv += g.J[k] * (in.qdot[g.joint[k]] - nzqd[g.joint[k]]);
    } else {
      wv += joint_velocity_[w];
    }
    u.noalias() = rot.T * wv;
    const double sc = frame_ == kinematics::WheelFrame::side_slip ? rot.cb : 1.0;
    u.x() = sc * u.x() / ((1.0 - x(ContactLayout::slip(w))) * m_->wheel_radius);
  } else {  // a joint-angle noise moves the wheel: its geometry again
    double qd[kMaxJoints], qn[kMaxJoints];
    for (int k = 0; k < g.nj; ++k) qd[g.joint[k]] = in.qdot[g.joint[k]] - nzqd[g.joint[k]];
    for (int i = 0; i < nq; ++i) qn[i] = in.q[i] - nzq[i];
    const WheelGeometry moved_geometry = wheel_geometry(*m_, w, qn);
    u = wheel_measurement(moved_geometry, rot.C, frame_, m_->wheel_radius, x.data() + 3, x(ContactLayout::slip(w)),
                          rot.cb, omega, qd);
  }
  for (int k = 0; k < 3; ++k) y(k * nw + w) = u(k) + nz(3 + 2 * nq + k * nw + w);
}

void WheelMeasurementModel::evaluate(const Eigen::VectorXd& x, const Eigen::VectorXd& n, Eigen::VectorXd& y) {
  y.resize(layout_.ny());
  for (int w = 0; w < layout_.nw; ++w) evaluate_wheel(w, x, n, y);
}

// Velocity and gyro reach every wheel, attitude none, a slip or angle its
// wheel, a joint its wheels.
void WheelMeasurementModel::evaluate_incremental(const Eigen::VectorXd& x, const Eigen::VectorXd& n,
                                                 const std::vector<Eigen::Index>& changed_x,
                                                 const std::vector<Eigen::Index>& changed_n, const Eigen::VectorXd& y0,
                                                 Eigen::VectorXd& y) {
  const int nq = layout_.nq;
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
      for (int w : wheels_of_joint_[static_cast<std::size_t>((i - 3) % nq)]) reach[w] = true;
    }
  }
  y = y0;
  for (int w = 0; w < layout_.nw; ++w) {
    if (all || reach[w]) evaluate_wheel(w, x, n, y);
  }
}

}  // namespace roverlab::estimation::contact
