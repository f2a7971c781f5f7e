#pragma once
// A ROS 1 bag's (format 2.0) chunks read record by record as the format
// defines them (wiki.ros.org/Bags/Format/2.0): the file header and the chunk
// info records of the index, then each chunk's connection and message data
// records, read and decompressed (bz2, lz4) by the rosbag library's own
// ChunkedFile. The library's per-message path (View and
// MessageInstance::instantiate: each record header parsed into a std::map, the
// view's iterators sorted again for every message) cost more than decoding
// every field of the message; here one pass over a chunk hands out each
// message's connection, record time and bytes where they lie.

#include <cstddef>
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace rosbag {
class ChunkedFile;
}

namespace roverlab::io::rosbag_chunks {

// A record or chunk not as format 2.0 writes it; what() is one line.
class FormatError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct ChunkInfo {
  std::uint64_t position = 0;  // of the chunk record in the file
  std::uint64_t start_ns = 0;  // record times of its earliest and latest messages
  std::uint64_t end_ns = 0;
};

struct BagIndex {
  std::vector<ChunkInfo> chunks;                    // in the index's order
  std::map<std::uint32_t, std::uint64_t> messages;  // per connection id, from the chunk infos
};

// The chunk info records of the index, or nullopt when the file header or
// the index is not as an unencrypted format 2.0 bag has it (the caller then
// reads through the library's View). A few kilobytes read.
std::optional<BagIndex> read_index(const std::string& path);

// Calls field(name, value) for each "name=value" field of a record header;
// false when the header is malformed.
template <class Field>
bool each_field(const std::uint8_t* header, std::size_t size, Field&& field);

// A message data record of a chunk: its connection, record time and bytes.
struct Message {
  std::uint32_t connection = 0;
  std::uint32_t sec = 0;
  std::uint32_t nsec = 0;
  const std::uint8_t* data = nullptr;
  std::uint32_t size = 0;

  std::int64_t time_ns() const { return static_cast<std::int64_t>(sec) * 1'000'000'000 + nsec; }
};

class ChunkReader {
 public:
  // Opens the file with the library's ChunkedFile (which throws rosbag::BagException).
  explicit ChunkReader(const std::string& path);
  ~ChunkReader();
  ChunkReader(const ChunkReader&) = delete;
  ChunkReader& operator=(const ChunkReader&) = delete;

  // Reads and decompresses the chunk at `position`; next() then hands out its
  // messages in file order. Throws FormatError. `library_calls_only`: an
  // uncompressed chunk's records are not read (only its header), for the
  // crash guard's trial, which need only make the library's calls.
  void load(std::uint64_t position, bool library_calls_only = false);

  // The chunk's next message data record (connection records are skipped);
  // false at the chunk's end. Throws FormatError on a malformed record.
  bool next(Message& m);

 private:
  [[noreturn]] void fail(const std::string& what) const;
  std::uint32_t u32(std::size_t at) const;

  std::unique_ptr<rosbag::ChunkedFile> file_;
  std::uint64_t file_size_ = 0;
  std::uint64_t position_ = 0;
  std::vector<std::uint8_t> compressed_;
  std::unique_ptr<std::uint8_t[]> records_;  // the decompressed chunk
  std::size_t capacity_ = 0;
  std::size_t size_ = 0;
  std::size_t at_ = 0;
  std::uint64_t decompressed_ = 0;  // over every chunk loaded
};

template <class Field>
bool each_field(const std::uint8_t* header, std::size_t size, Field&& field) {
  std::size_t at = 0;
  while (at < size) {
    if (size - at < 4) return false;
    std::uint32_t n = 0;
    for (int b = 3; b >= 0; --b) n = (n << 8) | header[at + static_cast<std::size_t>(b)];
    at += 4;
    if (n > size - at) return false;
    const std::string_view text(reinterpret_cast<const char*>(header + at), n);
    at += n;
    const std::size_t eq = text.find('=');
    if (eq == std::string_view::npos) return false;
    field(text.substr(0, eq), text.substr(eq + 1));
  }
  return true;
}

}  // namespace roverlab::io::rosbag_chunks
