#pragma once
// One log format = one LogReader. load_log (importers/log_file.h) asks every
// reader of importers/log_readers.def how sure it is that it reads a file and
// lets the surest one read it. Adding a format: one file defining the reader
// and its factory, one line in log_readers.def, the file in CMakeLists.txt.

#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "core/log/log.h"
#include "importers/mapping.h"

namespace roverlab::io {

struct LoadOptions {
  std::optional<Mapping> mapping;  // needed for MATLAB and foreign HDF5 files
  // ROS bags and MCAP files (importers/ros_message_log.h): a message's time is
  // its header.stamp (true) or its record time (false, the default), and
  // arrays longer than max_array elements are skipped.
  bool header_time = false;
  std::size_t max_array = 64;
  // ROS bags and MCAP files: only these topics ("/imu" or "imu"; all when
  // empty; a topic the file lacks is an error), and only the messages logged
  // from start_s to end_s seconds after the file's first message (times then
  // count from that first message). MCAP files with a summary read only the
  // chunks that hold them.
  std::vector<std::string> topics;
  std::optional<double> start_s;
  std::optional<double> end_s;
};

// How sure a reader is that a file is its own: by content first (a format
// marker beats a mere container signature), then by extension. When several
// readers are equally sure, the first in log_readers.def wins.
enum class Confidence {
  none = 0,       // not this reader's file
  extension = 1,  // only the file name's extension fits
  container = 2,  // the content is a container this reader reads (an HDF5 file)
  format = 3,     // the content carries this reader's format marker
};

class LogReader {
 public:
  virtual ~LogReader() = default;
  // What `roverlab info` prints as the format ("RoverLab HDF5 log").
  virtual std::string name() const = 0;
  // Looks at the file (it exists and is not a folder); never throws.
  virtual Confidence can_read(const std::string& path, const LoadOptions& options) const = 0;
  // Throws InputError naming the file and the problem.
  virtual log::Log read(const std::string& path, const LoadOptions& options) const = 0;
  // What load_log's crash guard runs in its forked child first
  // (importers/crash_guard.h): the library calls read() makes on the file;
  // the samples need not be kept. read() itself unless a reader does better.
  virtual void trial_read(const std::string& path, const LoadOptions& options) const { (void)read(path, options); }
  // A reader whose library may crash or hang on a damaged file names the
  // file kind and the library ("ROS bag", "rosbag library"): load_log then
  // runs trial_read under the crash guard. Empty strings: no guard (HDF5
  // files get it by their signature whatever the reader).
  virtual std::pair<std::string, std::string> crash_guard_names() const { return {}; }
};

// True when the file name ends in one of `extensions` (".h5"; case counts).
bool has_extension(const std::string& path, const std::vector<std::string>& extensions);

// The readers of log_readers.def, in its order.
const std::vector<std::unique_ptr<LogReader>>& log_readers();

// The reader that is surest to read `path`, or nullptr when none can.
const LogReader* find_log_reader(const std::string& path, const LoadOptions& options = {});

}  // namespace roverlab::io
