#include "importers/ros1_bag_chunks.h"

#include <algorithm>
#include <climits>
#include <cstdio>
#include <cstring>
#include <filesystem>

#include <rosbag/chunked_file.h>

namespace roverlab::io::rosbag_chunks {

namespace {

constexpr std::uint8_t kOpMessageData = 0x02;  // the op codes of format 2.0
constexpr std::uint8_t kOpFileHeader = 0x03;
constexpr std::uint8_t kOpChunk = 0x05;
constexpr std::uint8_t kOpChunkInfo = 0x06;
constexpr std::uint8_t kOpConnection = 0x07;
constexpr std::uint32_t kMaxHeader = 1U << 26;               // a record header is small (64 MiB at most)
constexpr std::uint64_t kMaxChunk = std::uint64_t{1} << 30;  // and a chunk at most 1 GiB decompressed

// A name from the file as a one-line message may hold it.
std::string printable(std::string_view text) {
  std::string out(text.substr(0, 40));
  for (char& c : out) {
    if (c < ' ' || c > '~') c = '?';
  }
  return out;
}

template <class T>
bool number(std::string_view bytes, T& v) {
  if (bytes.size() != sizeof(T)) return false;
  std::memcpy(&v, bytes.data(), sizeof v);
  return true;
}

// A time field (uint32 seconds, then uint32 nanoseconds) in nanoseconds.
bool time_field(std::string_view bytes, std::uint64_t& ns) {
  std::uint64_t packed = 0;
  if (!number(bytes, packed)) return false;
  ns = (packed & 0xffffffffU) * 1'000'000'000U + (packed >> 32);
  return true;
}

// The index records, read from the file with stdio (a few kilobytes).
class IndexFile {
 public:
  explicit IndexFile(const std::string& path) : in_(std::fopen(path.c_str(), "rb")) {}
  ~IndexFile() {
    if (in_ != nullptr) std::fclose(in_);
  }
  IndexFile(const IndexFile&) = delete;
  IndexFile& operator=(const IndexFile&) = delete;

  std::optional<BagIndex> read() {
    if (in_ == nullptr || std::fseek(in_, 13, SEEK_SET) != 0) return std::nullopt;  // after "#ROSBAG V2.0\n"
    std::uint64_t index_pos = 0;
    std::uint32_t connections = 0;
    std::uint32_t chunks = 0;
    bool encrypted = false;
    int op = -1;
    if (!record([&](std::string_view name, std::string_view value) {
          if (name == "op" && value.size() == 1) op = static_cast<std::uint8_t>(value[0]);
          if (name == "index_pos") (void)number(value, index_pos);
          if (name == "conn_count") (void)number(value, connections);
          if (name == "chunk_count") (void)number(value, chunks);
          if (name == "encryptor" && !value.empty()) encrypted = true;  // the library's plugin decrypts
        }) ||
        op != kOpFileHeader || encrypted || index_pos == 0 || index_pos > static_cast<std::uint64_t>(LONG_MAX) ||
        std::fseek(in_, static_cast<long>(index_pos), SEEK_SET) != 0) {
      return std::nullopt;
    }
    for (std::uint32_t k = 0; k < connections; ++k) {
      op = -1;
      if (!record([&](std::string_view name, std::string_view value) {
            if (name == "op" && value.size() == 1) op = static_cast<std::uint8_t>(value[0]);
          }) ||
          op != kOpConnection) {
        return std::nullopt;
      }
    }
    BagIndex index;
    for (std::uint32_t k = 0; k < chunks; ++k) {
      if (!chunk_info(index)) return std::nullopt;
    }
    // A chunk info past the header's count: the count lies, and the chunks it leaves out would be dropped.
    BagIndex more;
    if (chunk_info(more)) {
      throw FormatError("the file header counts " + std::to_string(chunks) + " chunks, its index lists more");
    }
    // A message record takes more than 40 bytes: counts the file could not hold are not believed.
    std::uint64_t total = 0;
    for (const auto& [connection, n] : index.messages) total += n;
    if (std::fseek(in_, 0, SEEK_END) != 0 || std::ftell(in_) < 0 ||
        total > static_cast<std::uint64_t>(std::ftell(in_)) / 40) {
      return std::nullopt;
    }
    return index;
  }

 private:
  bool chunk_info(BagIndex& index) {
    int op = -1;
    std::uint32_t version = 0;
    std::uint32_t count = 0;
    ChunkInfo info;
    bool has_position = false;
    if (!record([&](std::string_view name, std::string_view value) {
          if (name == "op" && value.size() == 1) op = static_cast<std::uint8_t>(value[0]);
          if (name == "ver") (void)number(value, version);
          if (name == "chunk_pos") has_position = number(value, info.position);
          if (name == "start_time") (void)time_field(value, info.start_ns);
          if (name == "end_time") (void)time_field(value, info.end_ns);
          if (name == "count") (void)number(value, count);
        }) ||
        op != kOpChunkInfo || version != 1 || !has_position || data_.size() != std::size_t{8} * count) {
      return false;
    }
    for (std::uint32_t e = 0; e < count; ++e) {
      std::uint32_t pair[2];
      std::memcpy(pair, data_.data() + std::size_t{8} * e, 8);
      index.messages[pair[0]] += pair[1];
    }
    index.chunks.push_back(info);
    return true;
  }

  // One record: its header's fields to `field`, its data in data_.
  template <class Field>
  bool record(Field&& field) {
    return block(header_) && each_field(header_.data(), header_.size(), field) && block(data_);
  }

  // A uint32 length and that many bytes (at most 64 MiB: an index record is small).
  bool block(std::vector<std::uint8_t>& out) {
    std::uint32_t n = 0;
    if (std::fread(&n, 4, 1, in_) != 1 || n > kMaxHeader) return false;
    out.resize(n);
    return n == 0 || std::fread(out.data(), 1, n, in_) == n;
  }

  std::FILE* in_;
  std::vector<std::uint8_t> header_;
  std::vector<std::uint8_t> data_;
};

}  // namespace

std::optional<BagIndex> read_index(const std::string& path) { return IndexFile(path).read(); }

ChunkReader::ChunkReader(const std::string& path) : file_(std::make_unique<rosbag::ChunkedFile>()) {
  file_->openRead(path);
  std::error_code ec;
  file_size_ = std::filesystem::file_size(path, ec);
  if (ec) fail("cannot tell its size");
}

ChunkReader::~ChunkReader() = default;

void ChunkReader::fail(const std::string& what) const {
  throw FormatError("the chunk at byte " + std::to_string(position_) + ": " + what);
}

std::uint32_t ChunkReader::u32(std::size_t at) const {
  std::uint32_t v = 0;
  std::memcpy(&v, records_.get() + at, 4);
  return v;
}

void ChunkReader::load(std::uint64_t position, bool library_calls_only) {
  position_ = position;
  size_ = at_ = 0;
  if (position > file_size_ || file_size_ - position < 8) fail("lies beyond the end of the file");
  file_->seek(position);
  std::uint32_t n = 0;
  file_->read(&n, 4);
  if (n > kMaxHeader || n > file_size_ - position - 8) fail("its header is longer than the file");
  compressed_.resize(n);
  if (n > 0) file_->read(compressed_.data(), n);
  int op = -1;
  std::string compression;
  std::uint32_t size = 0;
  bool has_size = false;
  if (!each_field(compressed_.data(), n, [&](std::string_view name, std::string_view value) {
        if (name == "op" && value.size() == 1) op = static_cast<std::uint8_t>(value[0]);
        if (name == "compression") compression = value;
        if (name == "size") has_size = number(value, size);
      })) {
    fail("its header is malformed");
  }
  if (op != kOpChunk || !has_size) fail("no chunk record there");
  std::uint32_t stored = 0;
  file_->read(&stored, 4);
  if (stored > file_size_ - position - 8 - n)
    fail("it claims " + std::to_string(stored) + " bytes, more than the file holds");
  if (size > kMaxChunk)
    fail("it claims " + std::to_string(size) + " bytes decompressed, more than RoverLab reads (1 GiB)");
  // Over the whole file: at most kMaxExpansion times its size (at least 256 MiB) decompressed.
  constexpr std::uint64_t kMaxExpansion = 1000;
  const std::uint64_t budget = std::max(std::uint64_t{256} << 20, kMaxExpansion * file_size_);
  decompressed_ += size;
  if (decompressed_ > budget) {
    fail("the chunks decompress to more than " + std::to_string(budget) +
         " bytes (1000 times the file's size, at least 256 MiB: the cap on decompressed bytes)");
  }
  rosbag::CompressionType type = rosbag::compression::Uncompressed;
  if (compression == "bz2") {
    type = rosbag::compression::BZ2;
  } else if (compression == "lz4") {
    type = rosbag::compression::LZ4;
  } else if (compression != "none") {
    fail("unknown compression '" + printable(compression) + "'");
  } else if (size != stored) {
    fail("uncompressed, but its sizes differ (" + std::to_string(size) + " and " + std::to_string(stored) + ")");
  }
  if (library_calls_only && type == rosbag::compression::Uncompressed) return;  // size_ = 0: no records
  if (size > capacity_) {
    records_.reset(new std::uint8_t[size]);
    capacity_ = size;
  }
  if (type == rosbag::compression::Uncompressed) {
    if (size > 0) file_->read(records_.get(), size);
  } else {
    compressed_.resize(stored);
    if (stored > 0) file_->read(compressed_.data(), stored);
    std::memset(records_.get(), 0, size);  // bz2 does not say when it fills fewer bytes
    file_->decompress(type, records_.get(), size, compressed_.data(), stored);
  }
  size_ = size;
}

bool ChunkReader::next(Message& m) {
  while (at_ < size_) {
    if (size_ - at_ < 4 || u32(at_) > size_ - at_ - 4) fail("a record's header runs past its end");
    const std::uint8_t* header = records_.get() + at_ + 4;
    const std::uint32_t header_size = u32(at_);
    at_ += 4 + std::size_t{header_size};
    if (size_ - at_ < 4 || u32(at_) > size_ - at_ - 4) fail("a record's data runs past its end");
    m.size = u32(at_);
    m.data = records_.get() + at_ + 4;
    at_ += 4 + std::size_t{m.size};
    int op = -1;
    bool has_connection = false;
    bool has_time = false;
    const bool parsed = each_field(header, header_size, [&](std::string_view name, std::string_view value) {
      if (name.size() == 2 && name == "op" && value.size() == 1) op = static_cast<std::uint8_t>(value[0]);
      if (name.size() != 4) return;
      if (name == "conn") has_connection = number(value, m.connection);
      if (name == "time" && value.size() == 8) {
        std::memcpy(&m.sec, value.data(), 4);
        std::memcpy(&m.nsec, value.data() + 4, 4);
        has_time = true;
      }
    });
    if (!parsed) fail("a record's header is malformed");
    if (op == kOpConnection) continue;  // the connections are the index's
    if (op != kOpMessageData) fail("a record of op " + std::to_string(op) + " where messages belong");
    if (!has_connection || !has_time) fail("a message record without its conn or time field");
    return true;
  }
  return false;
}

}  // namespace roverlab::io::rosbag_chunks
