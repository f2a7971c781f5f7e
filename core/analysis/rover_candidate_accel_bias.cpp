#include "core/analysis/rover_candidates.h"

namespace roverlab::analysis {

namespace {

class Candidate final : public RoverCandidate {
 public:
  const char* name() const override { return "accelerometer bias"; }
  const char* cause() const override { return "both accelerometer axes read a constant bias"; }
  bool physical() const override { return false; }
  std::vector<RoverCandidateParameter> parameters(const RoverResidualFeatures& features) const override {
    (void)features;
    return {{"accel-bias", "m/s^2", 0.0, -5.0, 5.0, 1e-4}};
  }
};

}  // namespace

std::unique_ptr<RoverCandidate> make_accel_bias_rover_candidate() { return std::make_unique<Candidate>(); }

}  // namespace roverlab::analysis
