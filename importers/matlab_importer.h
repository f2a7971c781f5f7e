#pragma once
// MATLAB v7.3 .mat files (HDF5 inside, after a 512-byte text header) and
// other HDF5 files whose numeric variables a mapping turns into a log.

#include <string>

#include "core/log/log.h"
#include "importers/mapping.h"

namespace roverlab::io {

enum class MatFileVersion { not_matlab, v7_3, older };

// Looks at the 128-byte MATLAB header: v7.3 (HDF5-based) or an older
// (v4/v5/v7) MAT-file that RoverLab cannot read.
MatFileVersion matlab_file_version(const std::string& path);

// Reads the variables the mapping names. Throws InputError naming the file:
// not HDF5, an older MAT-file, a variable the file lacks, a variable that is
// not numeric or whose shape does not fit its time base, bad time.
log::Log read_mapped_hdf5(const std::string& path, const Mapping& mapping);

}  // namespace roverlab::io
