#pragma once
// Opening any supported log file: RoverLab HDF5, MATLAB v7.3 or other HDF5
// through a mapping, or CSV. The readers of importers/log_readers.def
// recognise their files from the content, then the extension.

#include <string>

#include "core/log/log.h"
#include "importers/log_reader.h"

namespace roverlab::io {

struct LoadedLog {
  log::Log log;
  std::string format;  // the reader's name ("RoverLab HDF5 log", "CSV", ...)
};

// Throws InputError naming the file and the problem.
LoadedLog load_log(const std::string& path, const LoadOptions& options = {});

}  // namespace roverlab::io
