#include "importers/log_file.h"

#include <filesystem>

#include "core/common/error.h"
#include "importers/csv_log.h"
#include "importers/hdf5_log.h"
#include "importers/hdf5_support.h"
#include "importers/matlab_importer.h"

namespace roverlab::io {

namespace fs = std::filesystem;

const char* format_name(LogFormat format) {
  switch (format) {
    case LogFormat::roverlab_hdf5: return "RoverLab HDF5 log";
    case LogFormat::mapped_hdf5: return "HDF5 / MATLAB v7.3 through a mapping";
    case LogFormat::csv: return "CSV";
  }
  return "?";
}

LoadedLog load_log(const std::string& path, const LoadOptions& options) {
  std::error_code ec;
  if (!fs::exists(path, ec)) throw InputError(path, "no such file");
  if (fs::is_directory(path, ec)) throw InputError(path, "is a folder, not a log file");
  const MatFileVersion mat = matlab_file_version(path);
  if (h5::is_hdf5_file(path) || mat != MatFileVersion::not_matlab) {
    if (mat == MatFileVersion::not_matlab && is_roverlab_hdf5(path)) {
      return {read_hdf5_log(path), LogFormat::roverlab_hdf5};
    }
    if (!options.mapping) {
      if (mat == MatFileVersion::older) {
        throw InputError(path, "MAT-file older than v7.3 (not HDF5-based); re-save it in "
                               "MATLAB with save(FILE, '-v7.3')");
      }
      if (mat == MatFileVersion::v7_3) {
        throw InputError(path, "MATLAB file: pass --mapping NAME|FILE to say which variables "
                               "form which streams (see resources/mappings/)");
      }
      // Not a RoverLab log: the reader explains (corrupt, truncated or foreign).
      return {read_hdf5_log(path), LogFormat::roverlab_hdf5};
    }
    return {read_mapped_hdf5(path, *options.mapping), LogFormat::mapped_hdf5};
  }
  const std::string ext = fs::path(path).extension().string();
  if (ext == ".csv" || ext == ".CSV" || ext == ".txt") {
    return {read_csv_log(path), LogFormat::csv};
  }
  if (ext == ".h5" || ext == ".hdf5" || ext == ".mat") {
    throw InputError(path, "not an HDF5 file");
  }
  throw InputError(path, "unrecognised log format (expected HDF5 .h5, MATLAB v7.3 .mat or .csv)");
}

}  // namespace roverlab::io
