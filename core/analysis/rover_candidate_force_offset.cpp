#include "core/analysis/rover_candidates.h"

namespace roverlab::analysis {

namespace {

class Candidate final : public RoverCandidate {
 public:
  const char* name() const override { return "force offset"; }
  const char* cause() const override { return "every wheel force-sensor axis reads a constant offset"; }
  bool physical() const override { return false; }
  std::vector<RoverCandidateParameter> parameters(const RoverResidualFeatures& features) const override {
    (void)features;
    return {{"force-offset", "N", 0.0, -500.0, 500.0, 0.01}};
  }
};

}  // namespace

std::unique_ptr<RoverCandidate> make_force_offset_rover_candidate() { return std::make_unique<Candidate>(); }

}  // namespace roverlab::analysis
