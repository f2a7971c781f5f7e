#pragma once
// Opening any supported log file: RoverLab HDF5, MATLAB v7.3 or other HDF5
// through a mapping, or CSV. The format is recognised from the content, then
// the extension.

#include <optional>
#include <string>

#include "core/log/log.h"
#include "importers/mapping.h"

namespace roverlab::io {

enum class LogFormat { roverlab_hdf5, mapped_hdf5, csv };

struct LoadOptions {
  std::optional<Mapping> mapping;  // needed for MATLAB and foreign HDF5 files
};

struct LoadedLog {
  log::Log log;
  LogFormat format;
};

// Throws InputError naming the file and the problem.
LoadedLog load_log(const std::string& path, const LoadOptions& options = {});

const char* format_name(LogFormat format);

}  // namespace roverlab::io
