#include "core/discrepancy/single_wheel/candidates.h"

namespace roverlab::analysis {

namespace {

using terramechanics::Parameter;

// Wong & Reece (1967), Ishigami et al. (2007): the soil rebounds behind the
// bottom dead centre and the contact reaches theta_r = -kappa theta_1.
class RearAngle final : public SingleWheelCandidate {
 public:
  const char* name() const override { return "rear-angle"; }
  const char* cause() const override {
    return "the soil rebounds behind the wheel's lowest point and carries load and shear there";
  }
  std::vector<std::pair<Parameter, double>> parameters() const override { return {{Parameter::rear_angle_ratio, 0.2}}; }
};

}  // namespace

std::unique_ptr<SingleWheelCandidate> make_rear_angle_single_wheel_candidate() { return std::make_unique<RearAngle>(); }

}  // namespace roverlab::analysis
