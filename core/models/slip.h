#pragma once
// Slip ratio (seed 002 Eq. 1 and Eq. 30), its five classes (section 3.1) and
// column-normalised confusion matrices (Table 2).

#include <array>
#include <string>

namespace roverlab::estimation {

// Eq. 1: v body forward speed (m/s), wheel_speed = r omega (m/s).
// Positive when the wheels turn faster than the rover moves (slip), negative
// when slower (skid), 0 when equal or both zero; clamped to [-1, 1].
double slip_ratio(double v, double wheel_speed);

enum class SlipClass : int { none = 0, low = 1, medium = 2, high = 3, extreme = 4 };
inline constexpr int kSlipClasses = 5;
const char* to_string(SlipClass c);

// |s| <= no_slip: none; <= 0.2 low; <= 0.4 medium; <= 0.7 high; else extreme.
SlipClass classify_slip(double slip, double no_slip = 0.02);

struct ConfusionMatrix {
  // counts[estimated][truth]
  std::array<std::array<long, kSlipClasses>, kSlipClasses> counts{};
  void add(SlipClass estimated, SlipClass truth) { ++counts[static_cast<int>(estimated)][static_cast<int>(truth)]; }
  long truth_total(int truth) const;
  long total() const;
  // Column-normalised entry: share of truth class `truth` estimated as `estimated`.
  double fraction(int estimated, int truth) const;
  double accuracy() const;  // trace / total
};

}  // namespace roverlab::estimation
