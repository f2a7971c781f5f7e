#include "core/simulation/effects.h"

namespace roverlab::simulation {

// The pool's sizes run from half the smallest to three times the largest
// size an engineer would care about (docs/validation/discrepancy.md), except
// where the simulated rover would not move at all: a soil 7.5-90 % stronger
// or up to 1.3 times weaker (a soil 1.9 times weaker holds the flat_60s rover
// in place from the start), slip-sinkage n1 0.1-0.45 (at n1 = 0.65 the rover
// does not move in 60 s).
// The slip angle: 4-30 deg (below 4 deg the drawbar pull changes by less
// than 0.1 N at the flat_60s rover's slips; Ishigami 2007 Fig. 9 steers to 30 deg).
// The dropout's "size" is its start as a share of the run (20-80 %); the IMU
// time offset is not drawn (on a 2 cm/s drive it shows only in the start
// transient).
const std::vector<EffectSpec>& effect_table() {
  using E = RockerBogieEffects;
  static const std::vector<EffectSpec> table = {
      {"soil-strength", "1",
       "factor on the soil's c, tan(phi), kc, kphi (a soil too weak to carry the rover is refused)", 0.1, 10, true,
       &E::soil_strength, 1.0, 0.075, 0.9, true, 0.3},
      {"slip-sinkage", "1", "n1 of n = n0 + n1 |s|", 0, 2, true, &E::slip_sinkage_n1, 0.0, 0.1, 0.45, false},
      {"grousers", "m", "grouser height (24 grousers)", 0, 0.05, true, &E::grouser_height, 0.0, 0.002, 0.024, false},
      {"wheel-radius-scale", "1", "true wheel radius over the nominal one", 0.5, 2, true, &E::wheel_radius_scale, 1.0,
       0.01, 0.12, true},
      {"slip-angle", "deg",
       "every wheel's slip angle (a steering manoeuvre, or crabbing across a side slope): the Ishigami 2007 model, "
       "its magnitude (one planar side does not see its sign)",
       0, 60, true, &E::slip_angle_deg, 0.0, 4, 30, false},
      {"effect-start-x", "m", "where the physical effects begin (wheel centre x)", -1000, 1000, true,
       &E::effect_start_x, -1e9, 0, 0, false},
      {"gyro-bias", "rad/s", "bias on the pitch rate", -1, 1, false, &E::gyro_bias, 0.0, 0.00075, 0.009, true},
      {"accel-bias", "m/s^2", "bias on both accelerometer axes", -10, 10, false, &E::accel_bias, 0.0, 0.005, 0.06,
       true},
      {"force-offset", "N", "offset on every force-sensor axis", -1000, 1000, false, &E::force_offset, 0.0, 0.1, 1.5,
       true},
      {"force-scale", "1", "force-sensor scale factor", 0.1, 10, false, &E::force_scale, 1.0, 0.01, 0.12, true},
      {"encoder-dropout", "s", "start of 2 s in which the wheel encoders hold their value", 0, 100000, false,
       &E::encoder_dropout_start, -1.0, 0.2, 0.8, false},
      {"imu-time-offset", "s", "added to the imu stream's time stamps", -1, 1, false, &E::imu_time_offset, 0.0, 0, 0,
       true},
  };
  return table;
}

const EffectSpec* find_effect(const std::string& name) {
  for (const auto& e : effect_table()) {
    if (name == e.name) return &e;
  }
  return nullptr;
}

std::string effect_names() {
  std::string s;
  for (const auto& e : effect_table()) s += (s.empty() ? "" : ", ") + std::string(e.name);
  return s;
}

}  // namespace roverlab::simulation
