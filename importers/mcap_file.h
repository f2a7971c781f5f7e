#pragma once
// MCAP files (mcap.dev, format version 0), read from the specification: the
// records of the data section, chunks stored plain or compressed with zstd
// or lz4, and the summary section's chunk indexes when the file has them (a
// time range or a few topics then reads only the chunks that hold them); a
// linear scan of the data section otherwise. The CRC-32s the file holds (the
// summary's, each chunk's, and the data section's on a scan) are checked: a
// mismatch is an InputError, as damaged bytes would give wrong values. Messages encoded as `ros1`
// (schema `ros1msg`), `cdr` (schema `ros2msg`) or `json` are decoded as
// importers/ros_message_log.h describes.

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "core/log/log.h"
#include "importers/log_reader.h"

namespace roverlab::io {

// What to read: messages logged in [start_ns, end_ns] (the file's log times,
// nanoseconds) on the named topics (all when empty).
struct McapSelection {
  std::optional<std::uint64_t> start_ns;
  std::optional<std::uint64_t> end_ns;
  std::vector<std::string> topics;
};

// How a read went: bytes read from the file, and whether the summary's chunk
// indexes chose the chunks.
struct McapReadStats {
  std::uint64_t bytes_read = 0;
  bool indexed = false;
  std::uint64_t chunks_read = 0;     // chunks decompressed
  std::uint64_t chunks_in_file = 0;  // the summary's chunk indexes (a scan: the chunks it read)
};

// True when the file starts with MCAP's magic bytes.
bool has_mcap_magic(const std::string& path);

// Throws InputError naming the file and the problem.
log::Log read_mcap(const std::string& path, const LoadOptions& options, const McapSelection& selection = {},
                   McapReadStats* stats = nullptr);

}  // namespace roverlab::io
