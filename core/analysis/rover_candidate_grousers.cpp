#include "core/analysis/rover_candidates.h"

namespace roverlab::analysis {

namespace {

class Candidate final : public RoverCandidate {
 public:
  const char* name() const override { return "grousers"; }
  const char* cause() const override {
    return "the wheels carry grousers the smooth-wheel model lacks (24 grousers of a fitted height)";
  }
  bool physical() const override { return true; }
  std::vector<RoverCandidateParameter> parameters(const RoverResidualFeatures& features) const override {
    (void)features;
    return {{"grousers", "m", 0.002, 0.0, 0.05, 0.0005}};
  }
};

}  // namespace

std::unique_ptr<RoverCandidate> make_grousers_rover_candidate() { return std::make_unique<Candidate>(); }

}  // namespace roverlab::analysis
