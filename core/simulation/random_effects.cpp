#include "core/simulation/random_effects.h"

#include <array>
#include <random>

namespace roverlab::simulation {

namespace {

struct Pool {
  const char* cause;
  bool physical;
};

// The IMU time offset is not drawn: on a 2 cm/s drive it shows only in the
// start transient (docs/validation/discrepancy.md).
constexpr std::array<Pool, 9> kPool = {{{"soil-strength", true},
                                        {"slip-sinkage", true},
                                        {"grousers", true},
                                        {"wheel-radius-scale", true},
                                        {"gyro-bias", false},
                                        {"accel-bias", false},
                                        {"force-offset", false},
                                        {"force-scale", false},
                                        {"encoder-dropout", false}}};

void add(RandomEffects& out, const std::string& cause, std::mt19937& rng, double duration, double distance) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const double sign = u(rng) < 0.5 ? -1.0 : 1.0;
  const double a = u(rng);
  out.causes.push_back(cause);
  if (cause == "soil-strength") {
    out.effects.emplace_back("soil-strength", 0.85 - 0.15 * a);
    out.effects.emplace_back("effect-start-x", distance * (0.25 + 0.4 * u(rng)));
  } else if (cause == "slip-sinkage") {
    out.effects.emplace_back(cause, 0.2 + 0.2 * a);
  } else if (cause == "grousers") {
    out.effects.emplace_back(cause, 0.004 + 0.004 * a);
  } else if (cause == "wheel-radius-scale") {
    out.effects.emplace_back(cause, 1.0 + sign * (0.02 + 0.02 * a));
  } else if (cause == "gyro-bias") {
    out.effects.emplace_back(cause, sign * (0.0015 + 0.0015 * a));
  } else if (cause == "accel-bias") {
    out.effects.emplace_back(cause, sign * (0.01 + 0.01 * a));
  } else if (cause == "force-offset") {
    out.effects.emplace_back(cause, sign * (0.2 + 0.3 * a));
  } else if (cause == "force-scale") {
    out.effects.emplace_back(cause, 1.0 + sign * (0.02 + 0.02 * a));
  } else if (cause == "encoder-dropout") {
    out.effects.emplace_back(cause, duration * (0.2 + 0.6 * a));
  } else {
    out.effects.emplace_back(cause, sign * (0.1 + 0.1 * a));  // imu-time-offset
  }
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
  add(out, kPool[first].cause, rng, duration, distance);
  if (c <= 2) return out;
  std::size_t second = pick(rng);
  while (second == first || (kPool[first].physical && kPool[second].physical)) second = pick(rng);
  add(out, kPool[second].cause, rng, duration, distance);
  return out;
}

}  // namespace roverlab::simulation
