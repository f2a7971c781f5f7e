#pragma once
// How many seeds a calibration test runs: ROVERLAB_CALIBRATION_SEEDS when
// set (the full studies in docs/validation/discrepancy.md), else `ci`.

#include <cstdlib>

namespace roverlab::test {

inline unsigned calibration_seeds(unsigned ci) {
  const char* n = std::getenv("ROVERLAB_CALIBRATION_SEEDS");
  return n != nullptr ? static_cast<unsigned>(std::strtoul(n, nullptr, 10)) : ci;
}

}  // namespace roverlab::test
