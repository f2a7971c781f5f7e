#pragma once
// Measured single-wheel rows repeated to `rows`, at loads 60..100 N and with
// 3 % noise on every measurement: a long testbed file made from a short one
// (issue 29's 5,000-row example; the single-wheel study's benchmark).

#include <random>
#include <vector>

#include "core/terramechanics/wheel_test.h"

namespace roverlab::test {

inline std::vector<terramechanics::WheelTestPoint> resampled_wheel_test(
    const std::vector<terramechanics::WheelTestPoint>& measured, std::size_t rows) {
  std::mt19937 random(1);
  std::uniform_real_distribution<double> load(60.0, 100.0);
  std::normal_distribution<double> noise(1.0, 0.03);
  std::vector<terramechanics::WheelTestPoint> out;
  out.reserve(rows);
  for (std::size_t i = 0; i < rows; ++i) {
    terramechanics::WheelTestPoint p = measured[i % measured.size()];
    p.load = load(random);
    for (auto* m : {&p.drawbar_pull, &p.torque, &p.sinkage}) {
      if (*m) **m *= noise(random);
    }
    out.push_back(p);
  }
  return out;
}

}  // namespace roverlab::test
