// MATLAB v7.3 and other HDF5 files read through a mapping, as a LogReader.
#include "core/common/error.h"
#include "importers/hdf5_support.h"
#include "importers/log_reader.h"
#include "importers/matlab_importer.h"

namespace roverlab::io {

namespace {

class MappedHdf5Reader final : public LogReader {
 public:
  std::string name() const override { return "HDF5 / MATLAB v7.3 through a mapping"; }

  Confidence can_read(const std::string& path, const LoadOptions& options) const override {
    // Any MAT-file header, older ones included: read() explains what to do.
    if (matlab_file_version(path) != MatFileVersion::not_matlab) return Confidence::format;
    if (options.mapping && h5::is_hdf5_file(path)) return Confidence::container;
    return has_extension(path, {".mat"}) ? Confidence::extension : Confidence::none;
  }

  log::Log read(const std::string& path, const LoadOptions& options) const override {
    const MatFileVersion mat = matlab_file_version(path);
    if (mat == MatFileVersion::not_matlab && !h5::is_hdf5_file(path)) {
      throw InputError(path, "not an HDF5 file");  // chosen by its extension only
    }
    if (!options.mapping) {
      if (mat == MatFileVersion::older) {
        throw InputError(path,
                         "MAT-file older than v7.3 (not HDF5-based); re-save it in "
                         "MATLAB with save(FILE, '-v7.3')");
      }
      throw InputError(path,
                       "MATLAB file: pass --mapping NAME|FILE to say which variables "
                       "form which streams (see resources/mappings/)");
    }
    return read_mapped_hdf5(path, *options.mapping);
  }
};

}  // namespace

std::unique_ptr<LogReader> make_mapped_hdf5_log_reader() { return std::make_unique<MappedHdf5Reader>(); }

}  // namespace roverlab::io
