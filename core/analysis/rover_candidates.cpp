#include "core/analysis/rover_candidates.h"

namespace roverlab::analysis {

#define ROVERLAB_ROVER_CANDIDATE(x) std::unique_ptr<RoverCandidate> make_##x##_rover_candidate();
#include "core/analysis/rover_candidates.def"
#undef ROVERLAB_ROVER_CANDIDATE

std::vector<std::unique_ptr<RoverCandidate>> rover_candidates() {
  std::vector<std::unique_ptr<RoverCandidate>> out;
#define ROVERLAB_ROVER_CANDIDATE(x) out.push_back(make_##x##_rover_candidate());
#include "core/analysis/rover_candidates.def"
#undef ROVERLAB_ROVER_CANDIDATE
  return out;
}

}  // namespace roverlab::analysis
