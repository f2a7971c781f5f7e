#include "core/simulation/random_effects.h"

#include <algorithm>
#include <cmath>
#include <random>
#include <string>

#include "core/simulation/effects.h"

namespace roverlab::simulation {

namespace {

// The effects the pool draws from (pool_high > 0 in the table).
std::vector<const EffectSpec*> pool() {
  std::vector<const EffectSpec*> out;
  for (const auto& e : effect_table()) {
    if (e.pool_high > 0) out.push_back(&e);
  }
  return out;
}

// A size log-uniform in [pool_low, pool_high], a sign when the effect has
// one; a factor (neutral 1, unit "1") is multiplied by (1 + d)^+-1, so that a
// stronger and a weaker soil of the same size are equally likely and the
// factor stays positive; the dropout's size is its start as a share of the run.
void add(RandomEffects& out, const EffectSpec& e, std::mt19937& rng, double duration, double distance) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const double sign = e.signed_size && u(rng) < 0.5 ? -1.0 : 1.0;
  const double high = sign < 0 && e.pool_high_below > 0 ? e.pool_high_below : e.pool_high;
  const double d = e.pool_low * std::pow(high / e.pool_low, u(rng));
  double value = 0;
  if (std::string(e.name) == "encoder-dropout") {
    value = (e.pool_low + (e.pool_high - e.pool_low) * u(rng)) * duration;
  } else if (e.neutral == 1.0 && std::string(e.unit) == "1") {
    value = sign > 0 ? 1.0 + d : 1.0 / (1.0 + d);
  } else {
    value = e.neutral + sign * d;
  }
  out.causes.emplace_back(e.name);
  out.effects.emplace_back(e.name, value);
  // A soil change over the whole run (1 in 3) or from 25-65 % along the expected path.
  // Within the start's own range (a long fast run's 25-65 % can pass it): a draw is always a valid effect.
  if (std::string(e.name) == "soil-strength" && u(rng) >= 1.0 / 3.0) {
    const double start = distance * (0.25 + 0.4 * u(rng));
    for (const auto& spec : effect_table()) {
      if (std::string(spec.name) == "effect-start-x") {
        out.effects.emplace_back("effect-start-x", std::clamp(start, spec.lower, spec.upper));
      }
    }
  }
}

}  // namespace

RandomEffects random_effects(unsigned seed, double duration, double distance) {
  std::mt19937 rng(seed * 2654435761U + 12345U);
  std::uniform_int_distribution<int> count(0, 4);  // 0: none (1/5), 1-2: one (2/5), 3-4: two (2/5)
  const int c = count(rng);
  RandomEffects out;
  if (c == 0) return out;
  const std::vector<const EffectSpec*> p = pool();
  std::uniform_int_distribution<std::size_t> pick(0, p.size() - 1);
  const std::size_t first = pick(rng);
  add(out, *p[first], rng, duration, distance);
  if (c <= 2) return out;
  std::size_t second = pick(rng);
  while (second == first || (p[first]->physical && p[second]->physical)) second = pick(rng);
  add(out, *p[second], rng, duration, distance);
  return out;
}

}  // namespace roverlab::simulation
