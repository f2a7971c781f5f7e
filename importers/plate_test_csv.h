#pragma once
// Plate-sinkage tests as CSV (format in docs/plate-tests.md): a header line
// naming the plate, `# plate_diameter_m: 0.1` or `# plate_width_m: 0.05` with
// `# plate_length_m: 0.2`, then columns depth_m (positive into the soil) and
// force_N (positive when the soil pushes back); other columns are ignored.

#include <string>

#include "core/terramechanics/plate_test.h"

namespace roverlab::io {

// Throws InputError naming the file (and line): no plate size, a size out of
// (0, 10] m, a missing column, a ragged row, a cell that is not a number.
terramechanics::PlateRecord read_plate_test_csv(const std::string& path);

}  // namespace roverlab::io
