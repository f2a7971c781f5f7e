#include "core/discrepancy/single_wheel/candidates.h"

namespace roverlab::analysis {

namespace {

using terramechanics::Parameter;

// Ding et al. 2015 (J. Field Robotics 32, p. 827, doi:10.1002/rob.21533):
// the shear deformation modulus depends on slip, K = K_0 (1 + k_s s); K_0 is refitted with k_s since the
// static modulus is what the slip term scales.
class SlipShearModulus final : public SingleWheelCandidate {
 public:
  const char* name() const override { return "slip-shear-modulus"; }
  const char* cause() const override {
    return "the soil's shear deformation modulus changes with slip, so thrust builds up at another rate";
  }
  std::vector<std::pair<Parameter, double>> parameters() const override {
    return {{Parameter::shear_modulus_slip, 0.0}, {Parameter::shear_modulus, -1.0}};
  }
};

}  // namespace

std::unique_ptr<SingleWheelCandidate> make_slip_shear_modulus_single_wheel_candidate() {
  return std::make_unique<SlipShearModulus>();
}

}  // namespace roverlab::analysis
