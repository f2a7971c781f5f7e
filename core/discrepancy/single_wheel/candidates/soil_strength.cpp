#include "core/discrepancy/single_wheel/candidates.h"

namespace roverlab::analysis {

namespace {

using terramechanics::Parameter;

// One factor on the soil's strength.
class SoilStrength final : public SingleWheelCandidate {
 public:
  const char* name() const override { return "soil-strength"; }
  const char* cause() const override { return "the soil is uniformly weaker or stronger than its description"; }
  std::vector<std::pair<Parameter, double>> parameters() const override { return {{Parameter::soil_strength, 1.0}}; }
};

}  // namespace

std::unique_ptr<SingleWheelCandidate> make_soil_strength_single_wheel_candidate() {
  return std::make_unique<SoilStrength>();
}

}  // namespace roverlab::analysis
