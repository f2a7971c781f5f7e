#pragma once
// CSV logs: one stream per file. The first non-comment line is the header,
// cells "name [unit]" (no brackets: dimensionless); the time column is the one
// named "time" or "t", else the first. Lines starting with '#' are comments.
// Values are converted to SI on reading. An empty data cell is a missing
// sample (NaN); the time cell may never be empty.

#include <string>

#include "core/log/log.h"

namespace roverlab::io {

struct CsvOptions {
  std::string stream_name;  // default: the file's stem
};

// Throws InputError naming the file and, where it applies, the line.
log::Log read_csv_log(const std::string& path, const CsvOptions& options = {});

// Writes one stream atomically, values in shortest round-trip form.
void write_csv_stream(const log::Stream& stream, const std::string& path);

}  // namespace roverlab::io
