#include "core/discrepancy/odometry/candidates.h"

namespace roverlab::analysis {

namespace {

// A constant offset between the wheel and reference clocks.
class TimeOffset final : public OdometryCandidateModel {
 public:
  std::string name() const override { return "time offset"; }
  std::string cause() const override { return "the wheel and reference clocks disagree by a constant offset"; }
  std::vector<CandidateParameter> parameters() const override { return {{"time_offset_s", 0.0, -2.0, 2.0}}; }
  estimation::OdometryCorrections corrections(const double* x) const override {
    estimation::OdometryCorrections c;
    c.time_offset = x[0];
    return c;
  }
};

}  // namespace

std::unique_ptr<OdometryCandidateModel> make_time_offset_odometry_candidate(const OdometryCandidateContext&) {
  return std::make_unique<TimeOffset>();
}

}  // namespace roverlab::analysis
