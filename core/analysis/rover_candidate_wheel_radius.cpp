#include "core/analysis/rover_candidates.h"

namespace roverlab::analysis {

namespace {

class Candidate final : public RoverCandidate {
 public:
  const char* name() const override { return "wheel radius"; }
  const char* cause() const override {
    return "the wheels roll on another radius than the nominal one (controller and encoders assume the nominal)";
  }
  bool physical() const override { return true; }
  std::vector<RoverCandidateParameter> parameters(const RoverResidualFeatures& features) const override {
    (void)features;
    return {{"wheel-radius-scale", "1", 1.0, 0.8, 1.25, 0.002}};
  }
};

}  // namespace

std::unique_ptr<RoverCandidate> make_wheel_radius_rover_candidate() { return std::make_unique<Candidate>(); }

}  // namespace roverlab::analysis
