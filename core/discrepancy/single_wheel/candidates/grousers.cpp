#include "core/discrepancy/single_wheel/candidates.h"

namespace roverlab::analysis {

namespace {

using terramechanics::Parameter;

// Grousers add thrust the smooth-wheel model lacks (applies only to grousered wheels).
class Grousers final : public SingleWheelCandidate {
 public:
  const char* name() const override { return "grousers"; }
  const char* cause() const override { return "the grousered wheel pulls more than the smooth-wheel model predicts"; }
  std::vector<std::pair<Parameter, double>> parameters() const override {
    return {{Parameter::grouser_effectiveness, 0.5}};
  }
  bool needs_grousers() const override { return true; }
  // Both families: RFT reads grouser_effectiveness as a scale on the grousers' height (rft.h).
  bool belongs_to(terramechanics::ModelKind) const override { return true; }
  void configure(terramechanics::Extensions& e) const override { e.grousers = true; }
};

}  // namespace

std::unique_ptr<SingleWheelCandidate> make_grousers_single_wheel_candidate() { return std::make_unique<Grousers>(); }

}  // namespace roverlab::analysis
