#include "core/discrepancy/single_wheel/candidates.h"

namespace roverlab::analysis {

namespace {

using terramechanics::Parameter;

// RFT: sand heaped ahead of the faces that push it (the free surface raised by
// a fraction of the sinkage), which a flat-surface RFT lacks.
class PileUp final : public SingleWheelCandidate {
 public:
  const char* name() const override { return "pile-up"; }
  const char* cause() const override {
    return "sand piles up ahead of the faces that push it, so they meet deeper sand than the flat surface";
  }
  std::vector<std::pair<Parameter, double>> parameters() const override { return {{Parameter::rft_pileup, 0.3}}; }
  bool belongs_to(terramechanics::ModelKind kind) const override { return kind == terramechanics::ModelKind::rft; }
};

}  // namespace

std::unique_ptr<SingleWheelCandidate> make_pile_up_single_wheel_candidate() { return std::make_unique<PileUp>(); }

}  // namespace roverlab::analysis
