#include "core/models/reference_track.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

#include "core/log/stream.h"

namespace roverlab::estimation {

ReferenceTrack reference_from_gps(const log::Log& lg, const std::string& name) {
  ReferenceTrack r;
  const log::Stream* gps = lg.find_stream(name);
  if (gps == nullptr || gps->find_channel("east") == nullptr || gps->find_channel("north") == nullptr) return r;
  r.present = gps->size() >= 3;
  r.time = gps->time();
  r.east = gps->channel("east").values;
  r.north = gps->channel("north").values;
  r.up = gps->find_channel("up") ? gps->channel("up").values : std::vector<double>(r.time.size(), 0.0);
  if (gps->find_channel("latitude") && gps->find_channel("longitude") && !gps->empty()) {
    r.latitude = gps->channel("latitude").values.front();
    r.longitude = gps->channel("longitude").values.front();
    r.height = gps->find_channel("height") ? gps->channel("height").values.front() : 0.0;
  }
  const std::size_t n = r.time.size();
  r.v_east.assign(n, 0.0);
  r.v_north.assign(n, 0.0);
  for (std::size_t i = 0; i < n; ++i) {
    std::size_t a = i, b = i;
    while (a > 0 && r.time[i] - r.time[a - 1] <= 0.5) --a;
    while (b + 1 < n && r.time[b + 1] - r.time[i] <= 0.5) ++b;
    if (b > a) {
      r.v_east[i] = (r.east[b] - r.east[a]) / (r.time[b] - r.time[a]);
      r.v_north[i] = (r.north[b] - r.north[a]) / (r.time[b] - r.time[a]);
    }
  }
  return r;
}

double initial_course(const ReferenceTrack& ref, double distance, std::size_t from) {
  if (from >= ref.time.size()) return NAN;
  std::size_t k = from;
  auto away = [&](std::size_t i) { return std::hypot(ref.east[i] - ref.east[from], ref.north[i] - ref.north[from]); };
  while (k + 1 < ref.time.size() && away(k) < distance) ++k;
  return away(k) > 1.0 ? std::atan2(ref.east[k] - ref.east[from], ref.north[k] - ref.north[from]) : NAN;
}

double course_at(const ReferenceTrack& ref, double t, double min_speed) {
  const double ve = log::interpolate_linear(ref.time, ref.v_east, t);
  const double vn = log::interpolate_linear(ref.time, ref.v_north, t);
  if (!(std::hypot(ve, vn) >= min_speed)) return NAN;
  return std::atan2(ve, vn);
}

std::vector<double> distance_along(const ReferenceTrack& ref, double step) {
  // Summing every 10 Hz increment would add the position noise to the
  // distance; count a segment only once it is `step` long.
  std::vector<double> d(ref.time.size(), 0.0);
  const bool smooth = ref.smoothed && ref.smooth_east.size() == d.size();
  const std::vector<double>& east = smooth ? ref.smooth_east : ref.east;
  const std::vector<double>& north = smooth ? ref.smooth_north : ref.north;
  std::size_t anchor = 0;
  double total = 0.0;
  for (std::size_t i = 1; i < d.size(); ++i) {
    const double seg = std::hypot(east[i] - east[anchor], north[i] - north[anchor]);
    if (seg >= step) {
      total += seg;
      anchor = i;
    }
    d[i] = total;
  }
  return d;
}

}  // namespace roverlab::estimation

namespace roverlab::estimation {

namespace {

double median(std::vector<double> v) {
  if (v.empty()) return NAN;
  const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  return *mid;
}

// One constant-velocity Kalman filter (state east, v_east, north, v_north)
// over the fixes, and optionally its RTS smoother. Returns the negative log
// likelihood of the accepted innovations.
struct CvPass {
  const ReferenceTrack& ref;
  double q, r;  // process PSD, fix variance
  const GpsSmoothing& o;
  std::vector<Eigen::Vector4d> x_post, x_prior;
  std::vector<Eigen::Matrix4d> P_post, P_prior, Phi;
  std::vector<char> rejected;

  double filter() {
    const std::size_t n = ref.time.size();
    x_post.assign(n, Eigen::Vector4d::Zero());
    x_prior = x_post;
    P_post.assign(n, Eigen::Matrix4d::Zero());
    P_prior = P_post;
    Phi.assign(n, Eigen::Matrix4d::Identity());
    rejected.assign(n, 0);
    Eigen::Matrix<double, 2, 4> H = Eigen::Matrix<double, 2, 4>::Zero();
    H(0, 0) = H(1, 2) = 1.0;
    Eigen::Vector4d x(ref.east[0], 0.0, ref.north[0], 0.0);
    Eigen::Matrix4d P = Eigen::Vector4d(r, 100.0, r, 100.0).asDiagonal();  // velocity unknown
    double nll = 0;
    int in_row = 0;
    for (std::size_t i = 0; i < n; ++i) {
      if (i > 0) {
        const double dt = ref.time[i] - ref.time[i - 1];
        Eigen::Matrix4d F = Eigen::Matrix4d::Identity();
        F(0, 1) = F(2, 3) = dt;
        Eigen::Matrix2d Qa;
        Qa << dt * dt * dt / 3.0, dt * dt / 2.0, dt * dt / 2.0, dt;
        Eigen::Matrix4d Q = Eigen::Matrix4d::Zero();
        Q.block<2, 2>(0, 0) = q * Qa;
        Q.block<2, 2>(2, 2) = q * Qa;
        x = F * x;
        P = F * P * F.transpose() + Q;
        Phi[i] = F;
      }
      x_prior[i] = x;
      P_prior[i] = P;
      const Eigen::Vector2d nu(ref.east[i] - x(0), ref.north[i] - x(2));
      const Eigen::Matrix2d S = H * P * H.transpose() + r * Eigen::Matrix2d::Identity();
      const double nis = nu.dot(S.ldlt().solve(nu));
      if (i > 0 && nis > o.gate && in_row < o.max_rejected_in_row) {
        rejected[i] = 1;
        ++in_row;
      } else {
        in_row = 0;
        const Eigen::Matrix<double, 4, 2> K = P * H.transpose() * S.inverse();
        x += K * nu;
        P = (Eigen::Matrix4d::Identity() - K * H) * P;
        nll += 0.5 * (nis + std::log(S.determinant()));
      }
      x_post[i] = x;
      P_post[i] = P;
    }
    return nll;
  }

  void smooth() {
    for (std::size_t i = x_post.size() - 1; i-- > 0;) {
      const Eigen::Matrix4d A = P_post[i] * Phi[i + 1].transpose() * P_prior[i + 1].inverse();
      x_post[i] += A * (x_post[i + 1] - x_prior[i + 1]);
    }
  }
};

}  // namespace

void smooth_reference(ReferenceTrack& ref, const GpsSmoothing& o) {
  const std::size_t n = ref.time.size();
  if (!ref.present || n < 5) return;
  // Fix noise: white noise of sigma gives second differences of variance 6 sigma^2.
  std::vector<double> d2;
  for (std::size_t i = 1; i + 1 < n; ++i) {
    d2.push_back(std::abs(ref.east[i + 1] - 2.0 * ref.east[i] + ref.east[i - 1]));
    d2.push_back(std::abs(ref.north[i + 1] - 2.0 * ref.north[i] + ref.north[i - 1]));
  }
  const double sigma = std::max(o.min_fix_sigma, 1.4826 * median(d2) / std::sqrt(6.0));
  const double r = sigma * sigma;
  // Process noise: the most likely on a grid from a still rover to a lively one.
  double best_q = NAN, best_nll = INFINITY;
  for (double q = 1e-4; q <= 10.0 + 1e-9; q *= std::sqrt(10.0)) {
    CvPass pass{ref, q, r, o, {}, {}, {}, {}, {}, {}};
    const double nll = pass.filter();
    if (nll < best_nll) {
      best_nll = nll;
      best_q = q;
    }
  }
  CvPass pass{ref, best_q, r, o, {}, {}, {}, {}, {}, {}};
  pass.filter();
  pass.smooth();
  ref.smooth_east.resize(n);
  ref.smooth_north.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    ref.smooth_east[i] = pass.x_post[i](0);
    ref.v_east[i] = pass.x_post[i](1);
    ref.smooth_north[i] = pass.x_post[i](2);
    ref.v_north[i] = pass.x_post[i](3);
  }
  ref.outlier = pass.rejected;
  ref.fix_sigma = sigma;
  ref.accel_psd = best_q;
  ref.smoothed = true;
}

RigidAlignment rigid_alignment(const std::vector<double>& xe, const std::vector<double>& xn,
                               const std::vector<double>& ye, const std::vector<double>& yn) {
  RigidAlignment a;
  const std::size_t n = std::min({xe.size(), xn.size(), ye.size(), yn.size()});
  a.points = n;
  if (n < 2) return a;
  double mxe = 0, mxn = 0, mye = 0, myn = 0;
  for (std::size_t i = 0; i < n; ++i) {
    mxe += xe[i];
    mxn += xn[i];
    mye += ye[i];
    myn += yn[i];
  }
  const auto c = static_cast<double>(n);
  mxe /= c;
  mxn /= c;
  mye /= c;
  myn /= c;
  double A = 0, B = 0, spread = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const double ae = xe[i] - mxe, an = xn[i] - mxn, be = ye[i] - mye, bn = yn[i] - myn;
    A += ae * be + an * bn;
    B += an * be - ae * bn;
    spread += ae * ae + an * an;
  }
  a.rotation = std::atan2(B, A);
  const double cr = std::cos(a.rotation), sr = std::sin(a.rotation);
  a.east = mye - (cr * mxe + sr * mxn);
  a.north = myn - (-sr * mxe + cr * mxn);
  double ss = 0;
  for (std::size_t i = 0; i < n; ++i) {
    double e = xe[i], no = xn[i];
    apply_alignment(a, e, no);
    ss += (e - ye[i]) * (e - ye[i]) + (no - yn[i]) * (no - yn[i]);
  }
  a.residual_rms = std::sqrt(ss / c);
  if (n > 3 && spread > 0) a.rotation_sigma = std::sqrt(ss / (2.0 * (c - 3.0)) / spread);
  return a;
}

void apply_alignment(const RigidAlignment& a, double& east, double& north) {
  const double cr = std::cos(a.rotation), sr = std::sin(a.rotation);
  const double e = cr * east + sr * north + a.east;
  north = -sr * east + cr * north + a.north;
  east = e;
}

}  // namespace roverlab::estimation
