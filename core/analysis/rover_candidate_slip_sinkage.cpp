#include "core/analysis/rover_candidates.h"

namespace roverlab::analysis {

namespace {

class Candidate final : public RoverCandidate {
 public:
  const char* name() const override { return "slip-sinkage"; }
  const char* cause() const override {
    return "the wheels sink further as they slip (sinkage exponent n = n0 + n1 |s|)";
  }
  bool physical() const override { return true; }
  std::vector<RoverCandidateParameter> parameters(const RoverResidualFeatures& features) const override {
    (void)features;
    return {{"slip-sinkage", "1", 0.05, 0.0, 2.0, 0.01}};
  }
};

}  // namespace

std::unique_ptr<RoverCandidate> make_slip_sinkage_rover_candidate() { return std::make_unique<Candidate>(); }

}  // namespace roverlab::analysis
