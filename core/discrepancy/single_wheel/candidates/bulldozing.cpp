#include "core/discrepancy/single_wheel/candidates.h"

namespace roverlab::analysis {

namespace {

using terramechanics::Parameter;

// Bulldozing resistance of the soil pushed ahead of the wheel.
class Bulldozing final : public SingleWheelCandidate {
 public:
  const char* name() const override { return "bulldozing"; }
  const char* cause() const override { return "soil pushed ahead of the wheel resists its motion"; }
  std::vector<std::pair<Parameter, double>> parameters() const override { return {{Parameter::bulldozing_scale, 1.0}}; }
  void configure(terramechanics::Extensions& e) const override { e.bulldozing = true; }
};

}  // namespace

std::unique_ptr<SingleWheelCandidate> make_bulldozing_single_wheel_candidate() {
  return std::make_unique<Bulldozing>();
}

}  // namespace roverlab::analysis
