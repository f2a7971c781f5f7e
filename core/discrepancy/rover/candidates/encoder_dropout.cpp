#include "core/discrepancy/rover/candidates.h"

namespace roverlab::analysis {

namespace {

class EncoderDropoutCandidate final : public RoverCandidate {
 public:
  const char* name() const override { return "encoder dropout"; }
  const char* cause() const override { return "the wheel encoders stopped updating for 2 s (held their last value)"; }
  bool physical() const override { return false; }
  std::vector<RoverCandidateParameter> parameters(const RoverResidualFeatures& features) const override {
    if (!std::isfinite(features.hold_start)) return {};
    // The start is where the encoders stop changing; held, not fitted (a
    // discrete time known to one 50 Hz sample: uniform, sigma dt / sqrt(12)).
    RoverCandidateParameter p{"encoder-dropout", "s", features.hold_start, 0.0, 1e5, 0.02};
    p.fitted = false;
    p.resolution = 0.02 / std::sqrt(12.0);
    return {p};
  }
};

}  // namespace

std::unique_ptr<RoverCandidate> make_encoder_dropout_rover_candidate() {
  return std::make_unique<EncoderDropoutCandidate>();
}

}  // namespace roverlab::analysis
