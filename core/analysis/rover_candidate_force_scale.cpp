#include "core/analysis/rover_candidates.h"

namespace roverlab::analysis {

namespace {

class Candidate final : public RoverCandidate {
 public:
  const char* name() const override { return "force scale"; }
  const char* cause() const override { return "the wheel force sensors read with a wrong scale factor"; }
  bool physical() const override { return false; }
  std::vector<RoverCandidateParameter> parameters(const RoverResidualFeatures& features) const override {
    (void)features;
    return {{"force-scale", "1", 1.0, 0.2, 5.0, 1e-3}};
  }
};

}  // namespace

std::unique_ptr<RoverCandidate> make_force_scale_rover_candidate() { return std::make_unique<Candidate>(); }

}  // namespace roverlab::analysis
