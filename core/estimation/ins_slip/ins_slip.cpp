#include "core/estimation/ins_slip/ins_slip.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "core/estimation/ins_slip/estimator.h"

namespace roverlab::estimation {

std::string describe(const InitialHeading& h) {
  constexpr double deg = 180.0 / M_PI;
  char buf[256];
  switch (h.method) {
    case InitialHeading::Method::given:
      std::snprintf(buf, sizeof buf, "initial heading %.1f deg, given", h.heading * deg);
      break;
    case InitialHeading::Method::aligned:
      std::snprintf(buf, sizeof buf,
                    "initial heading %.1f +- %.1f deg, initial position (%.2f, %.2f) m: first pass aligned to %zu GPS "
                    "fixes over %.1f m of track (residual RMS %.2f m)",
                    h.heading * deg, h.sigma * deg, h.east, h.north, h.fixes, h.stretch, h.residual_rms);
      break;
    case InitialHeading::Method::assumed_north:
      std::snprintf(buf, sizeof buf, "initial heading unknown (no GPS track to align with): north assumed");
      break;
  }
  return buf;
}

InsSlipResult run_ins_slip(const log::Log& lg, const InsSlipOptions& o, const InsSlipChannels& names) {
  InsSlipResult result;
  InsSlipEstimator estimator(lg, o, names);
  result.estimates = estimator.run();
  result.health = estimator.health();
  result.heading = estimator.initial_heading();
  const ReferenceTrack& ref = estimator.reference();
  result.gps_fix_sigma = ref.fix_sigma;
  result.gps_accel_psd = ref.accel_psd;
  result.gps_outliers = static_cast<std::size_t>(std::count(ref.outlier.begin(), ref.outlier.end(), 1));
  result.no_slip = estimator.no_slip();
  result.vibration = estimator.vibration();
  const analysis::InsReferenceStreams reference{names.gps, names.truth_slip};
  result.metrics = analysis::score_ins_slip(lg, result.estimates, reference);
  result.odometry = analysis::score_wheel_odometry(lg, result.estimates, reference);
  return result;
}

}  // namespace roverlab::estimation
