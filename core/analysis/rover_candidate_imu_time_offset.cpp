#include "core/analysis/rover_candidates.h"

namespace roverlab::analysis {

namespace {

class Candidate final : public RoverCandidate {
 public:
  const char* name() const override { return "IMU time offset"; }
  const char* cause() const override { return "the IMU time stamps are offset from the other sensors' time stamps"; }
  bool physical() const override { return false; }
  std::vector<RoverCandidateParameter> parameters(const RoverResidualFeatures& features) const override {
    (void)features;
    return {{"imu-time-offset", "s", 0.0, -1.0, 1.0, 0.005}};
  }
};

}  // namespace

std::unique_ptr<RoverCandidate> make_imu_time_offset_rover_candidate() { return std::make_unique<Candidate>(); }

}  // namespace roverlab::analysis
