#include "core/estimation/contact_angle/ukf.h"

namespace roverlab::estimation {

namespace {

// The contact-angle models behind FixedUnscentedFilter::step_augmented's
// interface: fixed-size points to the models' dynamic-size arguments.
template <int NA>
struct UkfModel {
  using U = ContactAngleUkf<NA>;
  using State = typename U::Filter::State;
  using Measurement = typename U::Filter::Measurement;
  const contact::ContactProcessModel& process;
  contact::WheelMeasurementModel& measurement;
  const contact::Inputs& in;
  double ts;
  Eigen::VectorXd &xs, &np, &nm, &out, &y0, &y, &centre;
  std::vector<Eigen::Index>&changed_x, &changed_n;

  // f(x, n) with the IMU noise j (n_f, n_w: after the NX additive ones) = v.
  void f(const State& x, int j, double v, State& o) {
    xs = x;
    if (j >= 0) np(U::NX + j) = v;
    process.evaluate(xs, np, in, ts, out);
    if (j >= 0) np(U::NX + j) = 0.0;
    o = out;
  }
  void h(const State& x, Measurement& o) {
    centre = x;
    measurement.evaluate(centre, nm, y0);
    o = y0;
  }
  void h_moved(const State& x, const int* changed, int n, Measurement& o) {
    xs = x;
    changed_x.assign(changed, changed + n);
    changed_n.clear();
    measurement.evaluate_incremental(xs, nm, changed_x, changed_n, y0, y);
    o = y;
  }
  // h at the centre with the non-additive measurement noise j = v.
  void h_noise(int j, double v, Measurement& o) {
    changed_x.clear();
    changed_n.assign(1, j);
    nm(j) = v;
    measurement.evaluate_incremental(centre, nm, changed_x, changed_n, y0, y);
    nm(j) = 0.0;
    o = y;
  }
};

}  // namespace

template <int NA>
void ContactAngleUkf<NA>::set_noises(const Eigen::VectorXd& qdiag, const Eigen::VectorXd& r_ukf) {
  q_ = qdiag.head<NX>();
  qn_ = qdiag.segment<6>(NX);
  const auto nrn = static_cast<int>(r_ukf.size()) - NY;
  rn_.assign(r_ukf.data(), r_ukf.data() + nrn);
  r_ = r_ukf.tail<NY>();
  xs_.setZero(NX);
  centre_.setZero(NX);
  np_.setZero(NX + 6);
  nm_.setZero(r_ukf.size());
}

template <int NA>
bool ContactAngleUkf<NA>::step(const contact::ContactProcessModel& process, contact::WheelMeasurementModel& measurement,
                               const contact::Inputs& in, double ts, const Eigen::VectorXd& y) {
  UkfModel<NA> m{process, measurement, in, ts, xs_, np_, nm_, out_, y0_, y_, centre_, changed_x_, changed_n_};
  return filter.template step_augmented<6>(m, q_, qn_, rn_.data(), static_cast<int>(rn_.size()), r_, y);
}

template <int NA>
void ContactAngleUkf<NA>::predict(const contact::ContactProcessModel& process, const contact::Inputs& in, double ts) {
  xs_ = filter.x;
  process.evaluate(xs_, np_, in, ts, out_);
  filter.x = out_;
}

template class ContactAngleUkf<0>;
template class ContactAngleUkf<6>;
template class ContactAngleUkf<12>;

}  // namespace roverlab::estimation
