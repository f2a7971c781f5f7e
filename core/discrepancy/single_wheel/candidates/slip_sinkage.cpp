#include "core/discrepancy/single_wheel/candidates.h"

namespace roverlab::analysis {

namespace {

using terramechanics::Parameter;

// Ding et al. 2011: n = n0 + n1 |s|; n0 is refitted with n1 since the
// static exponent is what the slip term grows from.
class SlipSinkage final : public SingleWheelCandidate {
 public:
  const char* name() const override { return "slip-sinkage"; }
  const char* cause() const override { return "sinkage grows with slip and the static model cannot follow it"; }
  std::vector<std::pair<Parameter, double>> parameters() const override {
    return {{Parameter::slip_sinkage_n1, 0.0}, {Parameter::n, -1.0}};
  }
};

}  // namespace

std::unique_ptr<SingleWheelCandidate> make_slip_sinkage_single_wheel_candidate() {
  return std::make_unique<SlipSinkage>();
}

}  // namespace roverlab::analysis
