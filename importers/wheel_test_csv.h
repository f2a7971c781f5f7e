#pragma once
// Single-wheel test points from CSV, in the layout of
// ../shared/data/single_wheel/ding2011_tyii.csv: columns radius_m, width_m,
// load_N, slip and any of drawbar_pull_N, torque_Nm, sinkage_m; optional
// wheel, grouser_count, grouser_height_m, slip_angle_deg, lateral_force_N.
// Empty cells are unmeasured. Column order is free.

#include <string>
#include <vector>

#include "core/terramechanics/wheel_test.h"

namespace roverlab::io {

// Throws InputError naming the file and line: missing required column, no
// measured column, unparsable number, non-finite or out-of-range values.
std::vector<terramechanics::WheelTestPoint> read_wheel_test_csv(const std::string& path);

}  // namespace roverlab::io
