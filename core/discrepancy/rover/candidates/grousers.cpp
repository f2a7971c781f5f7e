#include "core/discrepancy/rover/candidates.h"

namespace roverlab::analysis {

std::unique_ptr<RoverCandidate> make_grousers_rover_candidate() {
  return fixed_rover_candidate(
      "grousers", "the wheels carry grousers the smooth-wheel model lacks (24 grousers of a fitted height)", true,
      {{"grousers", "m", 0.002, 0.0, 0.05, 0.0005}});
}

}  // namespace roverlab::analysis
