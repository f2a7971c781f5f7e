#pragma once
// A log: metadata and a set of streams, each with its own time base.

#include <cstddef>
#include <map>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

#include "core/log/stream.h"

namespace roverlab::log {

struct LogMetadata {
  std::string rover_id;                      // id of a rover description in resources/rovers/
  std::string source_file;                   // the file the log was imported from
  std::string description;                   // free text
  std::map<std::string, std::string> extra;  // further key/value pairs kept verbatim
  // Results stored with the log (`estimate X -o OUT.h5`): analysis name ->
  // its result document as JSON text, reused when input and settings match.
  std::map<std::string, std::string> results;
};

class Log {
 public:
  LogMetadata metadata;

  // Adds a stream; throws DataError when its name is taken. The reference is
  // valid until the next add_stream.
  Stream& add_stream(Stream stream);
  // Replaces the stream of that name in place (adds it when absent): an
  // estimator run again. References to the old stream's data are invalid.
  Stream& replace_stream(Stream stream);

  const std::vector<Stream>& streams() const { return streams_; }
  const Stream* find_stream(std::string_view name) const;
  const Stream& stream(std::string_view name) const;  // throws DataError when absent

  // "stream/channel" lookup, the channel being the part after the last '/':
  // "imu/accel_x", "truth/imu/accel_x". Throws DataError when absent.
  const Channel& channel(std::string_view path) const;

  // Every stream restricted to t0 <= t <= t1.
  Log slice(double t0, double t1) const;

  std::size_t total_samples() const;  // sum over streams of samples x (channels + time)
  std::size_t payload_bytes() const;  // total_samples() * sizeof(double)

 private:
  std::vector<Stream> streams_;
  // Stream index by name: a file of 65,535 topics is added and looked up in
  // linear time, not quadratic.
  std::unordered_map<std::string, std::size_t> index_;
};

}  // namespace roverlab::log
