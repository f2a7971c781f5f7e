#include "core/discrepancy/single_wheel/candidates.h"

namespace roverlab::analysis {

namespace {

using terramechanics::Parameter;

// Ishigami et al. 2007 (Eq. 7): the lateral shear stress builds up with its
// own shear-deformation modulus k_y, not the longitudinal K_s.
class LateralShearModulus final : public SingleWheelCandidate {
 public:
  const char* name() const override { return "lateral-shear-modulus"; }
  const char* cause() const override {
    return "the soil's lateral shear builds up at another rate than its longitudinal shear";
  }
  std::vector<std::pair<Parameter, double>> parameters() const override {
    return {{Parameter::lateral_shear_modulus, -1.0}};
  }
  bool needs_lateral_force() const override { return true; }
};

}  // namespace

std::unique_ptr<SingleWheelCandidate> make_lateral_shear_modulus_single_wheel_candidate() {
  return std::make_unique<LateralShearModulus>();
}

}  // namespace roverlab::analysis
