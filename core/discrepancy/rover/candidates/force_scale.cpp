#include "core/discrepancy/rover/candidates.h"

namespace roverlab::analysis {

std::unique_ptr<RoverCandidate> make_force_scale_rover_candidate() {
  return fixed_rover_candidate("force scale", "the wheel force sensors read with a wrong scale factor", false,
                               {{"force-scale", "1", 1.0, 0.2, 5.0, 1e-3}});
}

}  // namespace roverlab::analysis
