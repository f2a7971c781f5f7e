#pragma once
// The contact-angle UKF (seed 000, Eq. 2.18-2.20 over the models of
// contact_angle_model.h) on the fixed-size filter: one instance per model
// (NA = 0, 6, 12 angle states), instantiated in contact_angle_ukf.cpp only.
// Its estimates equal the generic UnscentedKalmanFilter's (the reference,
// ContactAngleOptions::reference_ukf) up to rounding.

#include <vector>

#include <Eigen/Core>

#include "core/estimation/contact_angle/model.h"
#include "core/filters/fixed_unscented_filter.h"

namespace roverlab::estimation {

template <int NA>
class ContactAngleUkf {
 public:
  static constexpr int NX = 12 + NA, NY = 18;
  using Filter = FixedUnscentedFilter<NX, NY>;
  Filter filter;

  // qdiag: the process noise variances (ContactLayout order: NX additive,
  // then n_f, n_w); r_ukf: the measurement noise variances in the UKF's
  // order (the non-additive first, the NY additive last).
  void set_noises(const Eigen::VectorXd& qdiag, const Eigen::VectorXd& r_ukf);
  // One predict-update cycle with this step's inputs (the measurement model's
  // set_inputs already called); false as FixedUnscentedFilter::step_augmented.
  bool step(const contact::ContactProcessModel& process, contact::WheelMeasurementModel& measurement,
            const contact::Inputs& in, double ts, const Eigen::VectorXd& y);
  // The mean through f at zero noise (a step without update; P kept).
  void predict(const contact::ContactProcessModel& process, const contact::Inputs& in, double ts);

 private:
  typename Filter::State q_;
  Eigen::Matrix<double, 6, 1> qn_;
  std::vector<double> rn_;
  typename Filter::Measurement r_;
  // The models' dynamic-size arguments, kept between calls.
  Eigen::VectorXd xs_, np_, nm_, out_, y0_, y_, centre_;
  std::vector<Eigen::Index> changed_x_, changed_n_;
};

extern template class ContactAngleUkf<0>;
extern template class ContactAngleUkf<6>;
extern template class ContactAngleUkf<12>;

}  // namespace roverlab::estimation
