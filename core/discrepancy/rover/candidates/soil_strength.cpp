#include "core/discrepancy/rover/candidates.h"

namespace roverlab::analysis {

namespace {

class SoilStrengthCandidate final : public RoverCandidate {
 public:
  const char* name() const override { return "soil strength change"; }
  const char* cause() const override {
    return "the soil changes strength where the rover drives (cohesion, friction and moduli scaled from a position on)";
  }
  bool physical() const override { return true; }
  std::vector<RoverCandidateParameter> parameters(const RoverResidualFeatures& features) const override {
    // Down to 0.3: the simulator refuses a TYII 0.23 times as strong (the
    // wheels would sink past their axles; issue 34, N10).
    // The change position starts where the logged torques start to depart from the simulation's.
    // Without a change in the residuals, or with one from the run's start, a
    // soil of another strength over the whole run.
    // A rover stuck (mean slip >= 0.9) where the nominal model rolls: only a
    // weaker soil stops it, and from the nominal strength the fit meets the
    // rolling-to-stuck edge and stops there (0.82 fitted for a true 0.5, 1.97
    // for 0.3); from near the lower bound it reaches the truth (0.3-0.7).
    const bool stuck = features.measured_slip >= 0.9 && features.model_slip < 0.9;
    const double start = stuck ? 0.45 : 1.0;
    if (!std::isfinite(features.change_x) || features.from_start)
      return {{"soil-strength", "1", start, 0.3, 5.0, 0.01}};
    const double x0 = features.change_x;
    return {{"soil-strength", "1", start, 0.3, 5.0, 0.01},
            {"effect-start-x", "m", x0, x0 - 0.3, x0 + 0.3, 0.002, true, 0, 0.05}};
  }
};

}  // namespace

std::unique_ptr<RoverCandidate> make_soil_strength_rover_candidate() {
  return std::make_unique<SoilStrengthCandidate>();
}

}  // namespace roverlab::analysis
