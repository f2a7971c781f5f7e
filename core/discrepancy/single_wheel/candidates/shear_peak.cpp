#include "core/discrepancy/single_wheel/candidates.h"

namespace roverlab::analysis {

namespace {

using terramechanics::Parameter;

// Wong, Theory of Ground Vehicles, ch. 2: dense sand and compact soils reach
// their maximum shear stress at a displacement K_w and fall to a residual
// K_r tau_max beyond it (the peaked, "hump" curve; model.h). Starts: K_r =
// 0.7 and K_w = 2 cm, inside the shipped soils' K_s range (1.1-2.5 cm).
class ShearPeak final : public SingleWheelCandidate {
 public:
  const char* name() const override { return "shear-peak"; }
  const char* cause() const override {
    return "the soil's shear stress peaks at a small shear displacement and falls to a residual value beyond it";
  }
  std::vector<std::pair<Parameter, double>> parameters() const override {
    return {{Parameter::shear_residual_ratio, 0.7}, {Parameter::shear_peak_displacement, 0.02}};
  }
  void configure(terramechanics::Extensions& e) const override { e.shear_peak = true; }
};

}  // namespace

std::unique_ptr<SingleWheelCandidate> make_shear_peak_single_wheel_candidate() { return std::make_unique<ShearPeak>(); }

}  // namespace roverlab::analysis
