#include "core/models/slip.h"

#include <algorithm>
#include <cmath>

namespace roverlab::estimation {

double slip_ratio(double v, double wheel_speed) {
  // Eq. 1 (seed 002); the sign follows the wheel's direction of rotation.
  if (v == wheel_speed || (v == 0.0 && wheel_speed == 0.0)) return 0.0;
  double s;
  if (std::abs(wheel_speed) > std::abs(v)) {
    s = 1.0 - v / wheel_speed;  // slipping
  } else {
    s = wheel_speed / v - 1.0;  // skidding
  }
  return std::clamp(s, -1.0, 1.0);
}

const char* to_string(SlipClass c) {
  switch (c) {
    case SlipClass::none:
      return "none";
    case SlipClass::low:
      return "low";
    case SlipClass::medium:
      return "medium";
    case SlipClass::high:
      return "high";
    case SlipClass::extreme:
      return "extreme";
  }
  return "?";
}

SlipClass classify_slip(double slip, double no_slip) {
  const double a = std::abs(slip);
  if (a <= no_slip) return SlipClass::none;
  if (a <= 0.2) return SlipClass::low;
  if (a <= 0.4) return SlipClass::medium;
  if (a <= 0.7) return SlipClass::high;
  return SlipClass::extreme;
}

long ConfusionMatrix::truth_total(int truth) const {
  long n = 0;
  for (int e = 0; e < kSlipClasses; ++e) n += counts[e][truth];
  return n;
}

long ConfusionMatrix::total() const {
  long n = 0;
  for (int t = 0; t < kSlipClasses; ++t) n += truth_total(t);
  return n;
}

double ConfusionMatrix::fraction(int estimated, int truth) const {
  const long n = truth_total(truth);
  return n > 0 ? static_cast<double>(counts[estimated][truth]) / static_cast<double>(n) : NAN;
}

double ConfusionMatrix::accuracy() const {
  long diag = 0;
  for (int k = 0; k < kSlipClasses; ++k) diag += counts[k][k];
  const long n = total();
  return n > 0 ? static_cast<double>(diag) / static_cast<double>(n) : NAN;
}

}  // namespace roverlab::estimation
