#include "core/estimation/contact_angle/contact_angle.h"

#include <utility>

#include "core/common/error.h"
#include "core/estimation/contact_angle/estimate_errors.h"
#include "core/estimation/contact_angle/estimator.h"
#include "core/estimation/contact_angle/two_filter.h"

namespace roverlab::estimation {

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

SmootherMethod parse_smoother_method(const std::string& s) {
  if (s == "two-filter") return SmootherMethod::two_filter;
  if (s == "rts") return SmootherMethod::rts;
  throw DataError("smoother '" + s + "': expected two-filter or rts");
}

AngleModel parse_angle_model(const std::string& s) {
  if (s == "random-walk") return AngleModel::random_walk;
  if (s == "damped") return AngleModel::damped;
  throw DataError("angle model '" + s + "': expected random-walk or damped");
}

ContactAngleResult run_contact_angle(const log::Log& lg, const kinematics::RoverModel& m,
                                     const ContactAngleOptions& o) {
  ContactAngleResult result = o.smoother && o.smoother_method == SmootherMethod::two_filter
                                  ? run_contact_angle_two_filter(lg, m, o)
                                  : ContactAngleEstimator(lg, m, o).run();
  // Without one wheel update the estimate is the IMU's prediction alone: no contact angle was measured.
  if (result.innovations.updates == 0) {
    throw DataError(
        "no wheel measurement update in the whole log: the wheels never turn (every wheel rate 0) or the joint "
        "angles are missing (NaN); nothing was estimated");
  }
  score_contact_angle(lg, result);
  return result;
}

void score_contact_angle(const log::Log& lg, ContactAngleResult& result) {
  if (auto errors = analysis::contact_angle_errors(lg, result.estimates)) {
    result.has_truth = true;
    result.rms = std::move(*errors);
  }
  if (result.smoothed) {
    if (auto errors = analysis::contact_angle_errors(lg, result.filter_estimates))
      result.filter_rms = std::move(*errors);
  }
}

}  // namespace roverlab::estimation
