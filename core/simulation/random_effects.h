#pragma once
// Hidden effects on demand (`roverlab simulate SCENARIO --effect random
// --seed N`): none, one or two effects of the planar rocker-bogie run and
// their sizes, drawn from the seed out of the effect table
// (core/simulation/effects.h; sizes from half to three times what an
// engineer would care about, both signs where an effect has one, a soil
// change over the whole run or from a position on; docs/validation/
// discrepancy.md). Two effects are never both physical (they would share
// the simulator's one start position).

#include <string>
#include <utility>
#include <vector>

#include "core/simulation/rocker_bogie.h"

namespace roverlab::simulation {

struct RandomEffects {
  std::vector<std::pair<std::string, double>> effects;  // set_effect names and values
  std::vector<std::string> causes;                      // the effects' cause names (soil-strength, gyro-bias, ...)
};

// `distance` (m): about how far the front wheel travels, so that a soil
// change falls on the path; `duration` (s) places an encoder dropout.
RandomEffects random_effects(unsigned seed, double duration, double distance);

}  // namespace roverlab::simulation
