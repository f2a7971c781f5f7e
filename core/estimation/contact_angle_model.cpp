#include "core/estimation/contact_angle_model.h"

#include <ceres/jet.h>

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
  auto joint = [&](int j, bool rate, int slot) {
    return j < 0 ? J(0.0) : J((rate ? in.qdot : in.q)[j], slot);
  };
  J out[3];
  wheel_measurement<J>(m, wheel, frame, vj, s, g, b, nw, joint(c.bogie_joint, false, 9), joint(c.steer_joint, false, 10),
                       joint(c.bogie_joint, true, 11), joint(c.steer_joint, true, 12), in, out);
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
  // its axle then by pi/2 about x; the side-slip frame turns by beta more.
  Eigen::Matrix3d C = Eigen::Matrix3d::Identity(), dC_dg = Eigen::Matrix3d::Zero(), dC_db = Eigen::Matrix3d::Zero();
  if (frame != kinematics::WheelFrame::drive) {
    const double cg = std::cos(gamma), sg = std::sin(gamma);
    Eigen::Matrix3d Rz, dRz;  // Rz(-gamma) and its derivative with respect to gamma
    Rz << cg, sg, 0, -sg, cg, 0, 0, 0, 1;
    dRz << -sg, cg, 0, -cg, -sg, 0, 0, 0, 0;
    Eigen::Matrix3d Rx;  // Rx(pi/2)
    Rx << 1, 0, 0, 0, 0, -1, 0, 1, 0;
    C = Rz * Rx;
    dC_dg = dRz * Rx;
    if (frame == kinematics::WheelFrame::side_slip) {
      const double cb = std::cos(beta), sb = std::sin(beta);
      Eigen::Matrix3d Rb, dRb;
      Rb << cb, -sb, 0, sb, cb, 0, 0, 0, 1;
      dRb << -sb, -cb, 0, cb, -sb, 0, 0, 0, 0;
      dC_db = C * dRb;
      dC_dg = dC_dg * Rb;
      C = C * Rb;
    }
  }
  const Eigen::Matrix3d Rt = (Rd * C).transpose();
  const Eigen::Vector3d wd = Rd.transpose() * w;
  const Eigen::Vector3d u = C.transpose() * wd;
  Eigen::Matrix<double, 3, 13> D = Eigen::Matrix<double, 3, 13>::Zero();
  D.leftCols<3>() = Rt;
  D.col(4) = dC_dg.transpose() * wd;
  D.col(5) = dC_db.transpose() * wd;
  Eigen::Matrix3d rx;  // d(omega x r)/d(gyro noise) = [r]x since omega = gyro - noise
  rx << 0, -r.z(), r.y(), r.z(), 0, -r.x(), -r.y(), r.x(), 0;
  D.block<3, 3>(0, 6) = Rt * rx;
  for (int k = 0; k < nj; ++k) {
    D.col(9 + k) = Rt * (dw[k] - z[k].cross(w));  // d(R^T w) = R^T (dw - z_k x w)
    D.col(11 + k) = Rt * Jq[k];
  }
  // Eq. 4.20 / Table 5.1: rate = (cos beta) u_x / ((1 - s) r), then u_y, u_z.
  const bool ss = frame == kinematics::WheelFrame::side_slip;
  const double den = (1.0 - slip) * m.wheel_radius, sc = ss ? std::cos(beta) : 1.0;
  WheelLinearization out;
  out.value = Eigen::Vector3d(sc * u.x() / den, u.y(), u.z());
  out.d = D;
  out.d.row(0) *= sc / den;
  out.d(0, 3) = sc * u.x() / ((1.0 - slip) * den);
  if (ss) out.d(0, 5) -= std::sin(beta) * u.x() / den;
  return out;
}

}  // namespace roverlab::estimation::contact
