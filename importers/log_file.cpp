#include "importers/log_file.h"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>

#include "core/common/error.h"
#include "importers/crash_guard.h"

namespace roverlab::io {

#define ROVERLAB_LOG_READER(NAME) std::unique_ptr<LogReader> make_##NAME##_log_reader();
#include "importers/log_readers.def"
#undef ROVERLAB_LOG_READER

namespace fs = std::filesystem;

bool has_extension(const std::string& path, const std::vector<std::string>& extensions) {
  const std::string ext = fs::path(path).extension().string();
  for (const auto& e : extensions) {
    if (ext == e) return true;
  }
  return false;
}

const std::vector<std::unique_ptr<LogReader>>& log_readers() {
  static const std::vector<std::unique_ptr<LogReader>> readers = [] {
    std::vector<std::unique_ptr<LogReader>> list;
#define ROVERLAB_LOG_READER(NAME) list.push_back(make_##NAME##_log_reader());
#include "importers/log_readers.def"
#undef ROVERLAB_LOG_READER
    return list;
  }();
  return readers;
}

const LogReader* find_log_reader(const std::string& path, const LoadOptions& options) {
  const LogReader* best = nullptr;
  Confidence best_confidence = Confidence::none;
  for (const auto& reader : log_readers()) {
    const Confidence c = reader->can_read(path, options);
    if (c > best_confidence) {
      best = reader.get();
      best_confidence = c;
    }
  }
  return best;
}

LoadedLog load_log(const std::string& path, const LoadOptions& options) {
  std::error_code ec;
  if (path.empty()) throw InputError("''", "the file name is empty");
  if (!fs::exists(path, ec)) throw InputError(path, "no such file");
  if (fs::is_directory(path, ec)) throw InputError(path, "is a folder, not a log file");
  // A pipe or a device never ends (and opening a pipe blocks): not a log.
  if (!fs::is_regular_file(path, ec)) throw InputError(path, "not a regular file (a pipe or a device?)");
  // A file we may not read is named so, not as "not an HDF5 file".
  if (std::FILE* probe = std::fopen(path.c_str(), "rb")) {
    std::fclose(probe);
  } else {
    throw InputError(path, std::string("cannot open: ") + std::strerror(errno));
  }
  // Recognising the file opens it with the HDF5 library too.
  const auto find = [&] {
    const LogReader* reader = find_log_reader(path, options);
    if (!reader)
      throw InputError(path,
                       "unrecognised log format (expected HDF5 .h5, MATLAB v7.3 .mat, .csv, ROS 1 .bag or .mcap)");
    return reader;
  };
  // The HDF5 library may crash on a damaged file: a child tries it first
  // (the reader's trial read: the same library calls, the samples dropped).
  if (has_hdf5_signature(path)) {
    survive_crash(path, [&] { find()->trial_read(path, options); });
  } else if (const LogReader* guarded = find_log_reader(path, options)) {
    const auto [format, library] = guarded->crash_guard_names();
    if (!format.empty())
      survive_crash(
          path, [&] { guarded->trial_read(path, options); }, format, library);
  }
  const LogReader* reader = find();
  return {reader->read(path, options), reader->name()};
}

}  // namespace roverlab::io
