#pragma once
// Hidden effects on demand (`roverlab simulate SCENARIO --effect random
// --seed N`): none, one or two effects of the planar rocker-bogie run and
// their sizes, drawn from the seed. Sizes are what an engineer would care
// about and no larger (docs/validation/discrepancy.md): a soil 15-30 %
// weaker from a position on, slip-sinkage n1 0.2-0.4, grousers 4-8 mm, a
// wheel radius 2-4 % off, a gyro bias 1.5-3 mrad/s, an accelerometer bias
// 0.01-0.02 m/s^2, a force offset 0.2-0.5 N, a force scale 2-4 % off, a 2 s
// encoder dropout. The IMU time offset is not drawn (it shows only in the
// start transient of a 2 cm/s drive). Two effects are never both physical
// (they would share the simulator's one start position).

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
