#include "core/discrepancy/single_wheel/candidates.h"

namespace roverlab::analysis {

#define ROVERLAB_SINGLE_WHEEL_CANDIDATE(x) std::unique_ptr<SingleWheelCandidate> make_##x##_single_wheel_candidate();
#include "core/discrepancy/single_wheel/candidates.def"
#undef ROVERLAB_SINGLE_WHEEL_CANDIDATE

std::vector<std::unique_ptr<SingleWheelCandidate>> single_wheel_candidates() {
  std::vector<std::unique_ptr<SingleWheelCandidate>> out;
#define ROVERLAB_SINGLE_WHEEL_CANDIDATE(x) out.push_back(make_##x##_single_wheel_candidate());
#include "core/discrepancy/single_wheel/candidates.def"
#undef ROVERLAB_SINGLE_WHEEL_CANDIDATE
  return out;
}

}  // namespace roverlab::analysis
