#pragma once
// RoverLab's own HDF5 log format, version 1 (docs/log-format.md).

#include <cstddef>
#include <memory>
#include <string>
#include <vector>

#include "core/log/log.h"

namespace roverlab::io {

inline constexpr int kLogFormatVersion = 1;
inline constexpr const char* kLogFormatName = "roverlab-log";

struct ChannelInfo {
  std::string name;
  std::string unit;
  std::string description;
};

struct StreamInfo {
  std::string name;
  std::size_t size = 0;
  std::vector<ChannelInfo> channels;
};

// Opens a RoverLab HDF5 log and reads its catalogue (names, units, sizes)
// without reading any samples; streams and single channels are then read on
// demand. Every failure is an InputError naming the file.
class Hdf5LogReader {
 public:
  explicit Hdf5LogReader(const std::string& path);
  ~Hdf5LogReader();
  Hdf5LogReader(const Hdf5LogReader&) = delete;
  Hdf5LogReader& operator=(const Hdf5LogReader&) = delete;

  const std::string& path() const { return path_; }
  int format_version() const { return format_version_; }
  const log::LogMetadata& metadata() const { return metadata_; }
  const std::vector<StreamInfo>& catalog() const { return catalog_; }

  // One channel's samples in SI units, read without touching the others.
  std::vector<double> read_channel(const std::string& stream, const std::string& channel) const;
  std::vector<double> read_time(const std::string& stream) const;
  log::Stream read_stream(const std::string& stream) const;
  log::Stream read_stream(const StreamInfo& stream) const;  // an entry of catalog()
  log::Log read_all() const;
  // Every dataset read_all reads, through the same library calls, into one
  // buffer that is then dropped: the crash guard's trial read
  // (importers/crash_guard.h) without a second log in memory.
  void read_all_discarding() const;

 private:
  void read_time_into(const std::string& stream, std::vector<double>& values) const;
  void read_channel_into(const std::string& stream, const std::string& channel, std::vector<double>& values) const;
  struct File;
  std::string path_;
  std::unique_ptr<File> file_;
  int format_version_ = 0;
  log::LogMetadata metadata_;
  std::vector<StreamInfo> catalog_;
};

// True when path is an HDF5 file carrying the RoverLab log format attribute.
bool is_roverlab_hdf5(const std::string& path);

log::Log read_hdf5_log(const std::string& path);

// Writes atomically (temporary file, then rename). Throws InputError naming
// the path when it cannot be written.
void write_hdf5_log(const log::Log& log, const std::string& path);
// The same for `base` with the streams of `added` after its own and added's
// metadata.extra entries over base's, without copying either log. A stream
// of `added` that `base` has too is a DataError ("appears twice"), as
// Log::add_stream.
void write_hdf5_log(const log::Log& base, const log::Log& added, const std::string& path);

}  // namespace roverlab::io
