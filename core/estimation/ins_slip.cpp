#include "core/estimation/ins_slip.h"

#include "core/estimation/ins_slip_estimator.h"

namespace roverlab::estimation {

InsSlipResult run_ins_slip(const log::Log& lg, const InsSlipOptions& o, const InsSlipChannels& names) {
  InsSlipResult result;
  InsSlipEstimator estimator(lg, o, names);
  result.estimates = estimator.run();
  result.health = estimator.health();
  const analysis::InsReferenceStreams reference{names.gps, names.truth_slip};
  result.metrics = analysis::score_ins_slip(lg, result.estimates, reference);
  result.odometry = analysis::score_wheel_odometry(lg, result.estimates, reference);
  return result;
}

}  // namespace roverlab::estimation
