#include "core/discrepancy/single_wheel/candidates.h"

namespace roverlab::analysis {

namespace {

using terramechanics::Parameter;

// Ishigami et al. 2007 (Eq. 10, after Hegedus): the sidewall bulldozes soil
// sideways; its resistance scaled (more soil heaped than the wedge predicts).
class Sidewall final : public SingleWheelCandidate {
 public:
  const char* name() const override { return "sidewall"; }
  const char* cause() const override {
    return "the wheel's sidewall bulldozes more (or less) soil sideways than Hegedus's wedge";
  }
  std::vector<std::pair<Parameter, double>> parameters() const override { return {{Parameter::sidewall_scale, 1.0}}; }
  bool needs_lateral_force() const override { return true; }
};

}  // namespace

std::unique_ptr<SingleWheelCandidate> make_sidewall_single_wheel_candidate() { return std::make_unique<Sidewall>(); }

}  // namespace roverlab::analysis
