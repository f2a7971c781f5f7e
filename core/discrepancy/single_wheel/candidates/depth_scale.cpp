#include "core/discrepancy/single_wheel/candidates.h"

namespace roverlab::analysis {

namespace {

using terramechanics::Parameter;

// RFT: the material scale grows (or falls) with depth, zeta (1 + k d / r),
// instead of Li 2013's stress linear in depth.
class DepthScale final : public SingleWheelCandidate {
 public:
  const char* name() const override { return "depth-scale"; }
  const char* cause() const override { return "the sand's resistance is not linear in depth (denser or looser below)"; }
  std::vector<std::pair<Parameter, double>> parameters() const override { return {{Parameter::rft_depth_scale, 0.5}}; }
  bool belongs_to(terramechanics::ModelKind kind) const override { return kind == terramechanics::ModelKind::rft; }
};

}  // namespace

std::unique_ptr<SingleWheelCandidate> make_depth_scale_single_wheel_candidate() {
  return std::make_unique<DepthScale>();
}

}  // namespace roverlab::analysis
