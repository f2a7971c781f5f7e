#include "core/discrepancy/rover/candidates.h"

namespace roverlab::analysis {

std::unique_ptr<RoverCandidate> make_slip_sinkage_rover_candidate() {
  return fixed_rover_candidate("slip-sinkage",
                               "the wheels sink further as they slip (sinkage exponent n = n0 + n1 |s|)", true,
                               {{"slip-sinkage", "1", 0.05, 0.0, 2.0, 0.01}});
}

}  // namespace roverlab::analysis
