#pragma once
// Single-wheel test points from CSV, in the layout of
// ../shared/data/single_wheel/ding2011_tyii.csv: columns radius_m, width_m,
// load_N, slip (or travel_slip / longitudinal_slip, stating the slip's
// definition) and any of drawbar_pull_N, torque_Nm, sinkage_m; optional
// wheel, grouser_count, grouser_height_m, slip_angle_deg, lateral_force_N.
// Empty cells are unmeasured. Column order is free. Sign conventions of the
// slip angle and the lateral force: core/terramechanics/wheel_test.h.

#include <string>
#include <vector>

#include "core/terramechanics/wheel_test.h"

namespace roverlab::io {

struct WheelTestFile {
  std::vector<terramechanics::WheelTestPoint> points;
  // One line per row left out ("line N left out: ..."), naming the value: a physically
  // impossible measurement (sinkage below 0 or beyond the wheel's diameter,
  // a slip angle beyond +-90 deg) excludes its row, not the file.
  std::vector<std::string> warnings;
  // "travel" or "longitudinal" when the file states how its slip is defined
  // (a column travel_slip or longitudinal_slip instead of slip); empty when
  // it does not.
  std::string slip_definition;
};

// Throws InputError naming the file and line: missing required column, no
// measured column, unparsable number, non-finite or out-of-range values of
// the wheel, load and slip, or no usable row.
WheelTestFile read_wheel_test_file(const std::string& path);

// The points alone (rows excluded with a warning are left out).
std::vector<terramechanics::WheelTestPoint> read_wheel_test_csv(const std::string& path);

}  // namespace roverlab::io
