// The RoverLab HDF5 log (docs/log-format.md) as a LogReader.
#include "importers/hdf5_log.h"
#include "importers/hdf5_support.h"
#include "importers/log_reader.h"
#include "importers/matlab_importer.h"

namespace roverlab::io {

namespace {

class RoverLabHdf5Reader final : public LogReader {
 public:
  std::string name() const override { return "RoverLab HDF5 log"; }

  Confidence can_read(const std::string& path, const LoadOptions& options) const override {
    if (h5::is_hdf5_file(path) && matlab_file_version(path) == MatFileVersion::not_matlab) {
      if (is_roverlab_hdf5(path)) return Confidence::format;
      // Without a mapping no other reader takes an HDF5 file: this one says
      // why it is not a RoverLab log (corrupt, truncated or foreign).
      if (!options.mapping) return Confidence::container;
    }
    return has_extension(path, {".h5", ".hdf5"}) ? Confidence::extension : Confidence::none;
  }

  log::Log read(const std::string& path, const LoadOptions&) const override { return read_hdf5_log(path); }
  // Each dataset into one reused buffer: no second copy of the log in the child.
  void trial_read(const std::string& path, const LoadOptions&) const override {
    Hdf5LogReader(path).read_all_discarding();
  }
};

}  // namespace

std::unique_ptr<LogReader> make_roverlab_hdf5_log_reader() { return std::make_unique<RoverLabHdf5Reader>(); }

}  // namespace roverlab::io
