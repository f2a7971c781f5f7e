#include "core/simulation/random_effects.h"

#include <array>
#include <random>
#include <string>

namespace roverlab::simulation {

namespace {

// A cause and its size: value = base + sign * (low + span * a), a uniform in
// [0, 1), sign +-1 at random when `signed_size` (else +1); the dropout's
// start is that value times the run's duration.
struct Pool {
  const char* cause;
  bool physical, signed_size;
  double base, low, span;
};

// The IMU time offset is not drawn: on a 2 cm/s drive it shows only in the
// start transient (docs/validation/discrepancy.md).
constexpr std::array<Pool, 9> kPool = {{{"soil-strength", true, false, 0.85, 0.0, -0.15},
                                        {"slip-sinkage", true, false, 0.0, 0.2, 0.2},
                                        {"grousers", true, false, 0.0, 0.004, 0.004},
                                        {"wheel-radius-scale", true, true, 1.0, 0.02, 0.02},
                                        {"gyro-bias", false, true, 0.0, 0.0015, 0.0015},
                                        {"accel-bias", false, true, 0.0, 0.01, 0.01},
                                        {"force-offset", false, true, 0.0, 0.2, 0.3},
                                        {"force-scale", false, true, 1.0, 0.02, 0.02},
                                        {"encoder-dropout", false, false, 0.0, 0.2, 0.6}}};

void add(RandomEffects& out, const Pool& p, std::mt19937& rng, double duration, double distance) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const double sign = u(rng) < 0.5 ? -1.0 : 1.0;
  const double a = u(rng);
  out.causes.emplace_back(p.cause);
  double value = p.base + (p.signed_size ? sign : 1.0) * (p.low + p.span * a);
  if (std::string(p.cause) == "encoder-dropout") value *= duration;
  out.effects.emplace_back(p.cause, value);
  // A soil change starts 25-65 % along the expected path.
  if (std::string(p.cause) == "soil-strength")
    out.effects.emplace_back("effect-start-x", distance * (0.25 + 0.4 * u(rng)));
}

}  // namespace

RandomEffects random_effects(unsigned seed, double duration, double distance) {
  std::mt19937 rng(seed * 2654435761U + 12345U);
  std::uniform_int_distribution<int> count(0, 4);  // 0: none (1/5), 1-2: one (2/5), 3-4: two (2/5)
  const int c = count(rng);
  RandomEffects out;
  if (c == 0) return out;
  std::uniform_int_distribution<std::size_t> pick(0, kPool.size() - 1);
  const std::size_t first = pick(rng);
  add(out, kPool[first], rng, duration, distance);
  if (c <= 2) return out;
  std::size_t second = pick(rng);
  while (second == first || (kPool[first].physical && kPool[second].physical)) second = pick(rng);
  add(out, kPool[second], rng, duration, distance);
  return out;
}

}  // namespace roverlab::simulation
