#include "core/discrepancy/single_wheel/candidates.h"

namespace roverlab::analysis {

namespace {

using terramechanics::Parameter;

// Wong & Reece (1967): the maximum normal stress sits at
// theta_m = (c1 + c2 s) theta_1 (Eq. 2.10, seed 003); the soil's c1, c2 are
// Wong's loose-sand values, refitted here.
class MaxStressAngle final : public SingleWheelCandidate {
 public:
  const char* name() const override { return "max-stress-angle"; }
  const char* cause() const override {
    return "the peak of the normal stress sits elsewhere under the wheel, and moves with slip differently";
  }
  std::vector<std::pair<Parameter, double>> parameters() const override {
    return {{Parameter::c1, -1.0}, {Parameter::c2, -1.0}};
  }
};

}  // namespace

std::unique_ptr<SingleWheelCandidate> make_max_stress_angle_single_wheel_candidate() {
  return std::make_unique<MaxStressAngle>();
}

}  // namespace roverlab::analysis
