#pragma once
// The planar rocker-bogie simulator's injectable effects as one table (issue
// 29): name, unit, allowed range, physical or sensor, and the random pool's
// sizes. set_effect, the simulator's truth metadata, `simulate --help`, the
// random pool (random_effects.cpp) and the discrepancy candidates' checks all
// read it; a new effect is one row here plus its use in the simulator.

#include <string>
#include <vector>

#include "core/simulation/rocker_bogie.h"

namespace roverlab::simulation {

struct EffectSpec {
  const char* name;     // as in `simulate --effect NAME=VALUE`
  const char* unit;     // "1" for a factor
  const char* what;     // plain words
  double lower, upper;  // allowed values (inclusive)
  bool physical;        // true: changes the run (a new simulation); false: applied to the sensor series
  double RockerBogieEffects::*member;
  double neutral;  // the value that means "no effect"
  // The random pool (`simulate --effect random`): a deviation from neutral of
  // size log-uniform in [pool_low, pool_high], of either sign when
  // signed_size (else +). pool_high = 0: not drawn.
  double pool_low, pool_high;
  bool signed_size;
  double pool_high_below = 0;  // > 0: the largest deviation drawn below neutral, when smaller than pool_high
};

const std::vector<EffectSpec>& effect_table();
// nullptr when the name is not an effect.
const EffectSpec* find_effect(const std::string& name);
// "soil-strength, slip-sinkage, ...", in table order.
std::string effect_names();

}  // namespace roverlab::simulation
