// MCAP files (importers/mcap_file.h) as a LogReader. Written from the
// specification at mcap.dev (format version 0); every length in the file is
// checked against what the file (or the chunk) holds before it is used.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <map>
#include <memory>
#include <new>
#include <set>

#include <lz4frame.h>
#include <zlib.h>
#include <zstd.h>

#include "core/common/error.h"
#include "importers/mcap_file.h"
#include "importers/ros_message_log.h"

namespace roverlab::io {

namespace {

constexpr std::uint8_t kMagic[8] = {0x89, 'M', 'C', 'A', 'P', '0', '\r', '\n'};
// A chunk larger than this uncompressed is refused (writers use about 1 MB).
constexpr std::uint64_t kMaxChunk = std::uint64_t{1} << 30;

enum Opcode : std::uint8_t {
  kHeader = 0x01,
  kFooter = 0x02,
  kSchema = 0x03,
  kChannel = 0x04,
  kMessage = 0x05,
  kChunk = 0x06,
  kChunkIndex = 0x08,
  kStatistics = 0x0B,
  kDataEnd = 0x0F,
};

// A problem with the file's bytes; read_mcap names the file.
struct McapError {
  std::string problem;
};

std::string hex(std::uint64_t v) {
  char text[32];
  std::snprintf(text, sizeof text, "0x%llx", static_cast<unsigned long long>(v));
  return text;
}

// CRC-32 (the zlib / ISO-HDLC one the spec names) of `n` bytes, continuing `crc`.
std::uint32_t crc32_of(std::uint32_t crc, const std::uint8_t* data, std::uint64_t n) {
  while (n > 0) {
    const auto part = static_cast<uInt>(std::min<std::uint64_t>(n, std::uint64_t{1} << 30));
    crc = static_cast<std::uint32_t>(crc32(crc, data, part));
    data += part;
    n -= part;
  }
  return crc;
}

std::string crc_text(std::uint32_t v) {
  char text[16];
  std::snprintf(text, sizeof text, "%08x", v);
  return text;
}

// Little-endian fields of one record's content, bounds-checked.
class Cursor {
 public:
  Cursor(const std::uint8_t* data, std::size_t size, const char* record) : data_(data), size_(size), record_(record) {}

  template <class T>
  T number() {
    need(sizeof(T));
    T v;
    std::memcpy(&v, data_ + pos_, sizeof(T));
    pos_ += sizeof(T);
    return v;
  }
  std::string string() {
    const auto n = number<std::uint32_t>();
    need(n);
    std::string s(reinterpret_cast<const char*>(data_ + pos_), n);
    pos_ += n;
    return s;
  }
  // Bytes prefixed by a uint32 (or uint64) length: where they start, and how many.
  template <class Length>
  std::pair<const std::uint8_t*, std::size_t> bytes() {
    const auto n = number<Length>();
    need(n);
    const std::uint8_t* start = data_ + pos_;
    pos_ += static_cast<std::size_t>(n);
    return {start, static_cast<std::size_t>(n)};
  }
  std::pair<const std::uint8_t*, std::size_t> rest() {
    const std::pair<const std::uint8_t*, std::size_t> r{data_ + pos_, size_ - pos_};
    pos_ = size_;
    return r;
  }

 private:
  void need(std::uint64_t n) const {
    if (n > size_ - pos_) {
      throw McapError{std::string(record_) + " record of " + std::to_string(size_) + " bytes ends inside a field"};
    }
  }
  const std::uint8_t* data_;
  std::size_t size_;
  std::size_t pos_ = 0;
  const char* record_;
};

class File {
 public:
  explicit File(const std::string& path) : file_(std::fopen(path.c_str(), "rb")) {
    if (file_ == nullptr) throw McapError{"cannot open the file"};
    if (std::fseek(file_, 0, SEEK_END) != 0) throw McapError{"cannot seek in the file"};
    const long end = std::ftell(file_);
    if (end < 0) throw McapError{"cannot tell the file's size"};
    size_ = static_cast<std::uint64_t>(end);
  }
  ~File() { std::fclose(file_); }
  File(const File&) = delete;
  File& operator=(const File&) = delete;

  std::uint64_t size() const { return size_; }
  std::uint64_t bytes_read() const { return bytes_read_; }

  void read(std::uint64_t offset, std::uint64_t n, std::vector<std::uint8_t>& out) {
    if (offset > size_ || n > size_ - offset) {
      throw McapError{std::to_string(n) + " bytes at offset " + std::to_string(offset) + " run past the end of the " +
                      std::to_string(size_) + "-byte file (truncated?)"};
    }
    out.resize(static_cast<std::size_t>(n));
    if (std::fseek(file_, static_cast<long>(offset), SEEK_SET) != 0 ||
        (n > 0 && std::fread(out.data(), 1, out.size(), file_) != out.size())) {
      throw McapError{"cannot read " + std::to_string(n) + " bytes at offset " + std::to_string(offset)};
    }
    bytes_read_ += n;
  }

 private:
  std::FILE* file_;
  std::uint64_t size_ = 0;
  std::uint64_t bytes_read_ = 0;
};

struct SchemaRecord {
  std::string name;
  std::string encoding;
  std::string data;
};

struct ChannelRecord {
  std::string topic;
  std::string message_encoding;
  std::uint16_t schema = 0;
  std::optional<std::size_t> topic_index;  // in the MessageLog, once a message came
};

struct ChunkIndexRecord {
  std::uint64_t start_time = 0;
  std::uint64_t end_time = 0;
  std::uint64_t offset = 0;
  std::uint64_t length = 0;
  std::set<std::uint16_t> channels;
};

std::vector<std::uint8_t> decompress(const std::string& compression, const std::uint8_t* data, std::size_t size,
                                     std::uint64_t uncompressed_size) {
  if (uncompressed_size > kMaxChunk) {
    throw McapError{"a chunk claims " + std::to_string(uncompressed_size) + " bytes uncompressed (more than 1 GiB)"};
  }
  std::vector<std::uint8_t> out;
  if (compression.empty()) {
    if (size != uncompressed_size) {
      throw McapError{"an uncompressed chunk holds " + std::to_string(size) + " bytes but claims " +
                      std::to_string(uncompressed_size)};
    }
    out.assign(data, data + size);
    return out;
  }
  out.resize(static_cast<std::size_t>(uncompressed_size));
  if (compression == "zstd") {
    const std::size_t got = ZSTD_decompress(out.data(), out.size(), data, size);
    if (ZSTD_isError(got) != 0U) throw McapError{std::string("zstd chunk: ") + ZSTD_getErrorName(got)};
    if (got != out.size()) {
      throw McapError{"zstd chunk gives " + std::to_string(got) + " bytes, claims " + std::to_string(out.size())};
    }
    return out;
  }
  if (compression == "lz4") {
    LZ4F_dctx* context = nullptr;
    if (LZ4F_isError(LZ4F_createDecompressionContext(&context, LZ4F_VERSION)) != 0U) {
      throw McapError{"lz4: no decompression context"};
    }
    std::size_t in = 0;
    std::size_t produced = 0;
    std::size_t status = 1;
    while (in < size && status != 0) {
      std::size_t src = size - in;
      std::size_t dst = out.size() - produced;
      status = LZ4F_decompress(context, out.data() + produced, &dst, data + in, &src, nullptr);
      if (LZ4F_isError(status) != 0U) {
        const std::string why = LZ4F_getErrorName(status);
        LZ4F_freeDecompressionContext(context);
        throw McapError{"lz4 chunk: " + why};
      }
      in += src;
      produced += dst;
      if (src == 0 && dst == 0) break;  // no progress: the output is full or the frame is cut
    }
    LZ4F_freeDecompressionContext(context);
    if (status != 0 || produced != out.size()) {
      throw McapError{"lz4 chunk gives " + std::to_string(produced) + " bytes, claims " + std::to_string(out.size()) +
                      (status != 0 ? " (the frame is cut short)" : "")};
    }
    return out;
  }
  throw McapError{"chunk compression '" + compression + "' is not supported (RoverLab reads none, lz4 and zstd)"};
}

class McapReader {
 public:
  McapReader(const std::string& path, const LoadOptions& options, const McapSelection& selection)
      : path_(path),
        options_(options),
        file_(path),
        start_ns_(selection.start_ns),
        end_ns_(selection.end_ns),
        relative_(!selection.start_ns && !selection.end_ns && (options.start_s || options.end_s)),
        messages_(path, message_options(options)) {
    for (const auto& t : selection.topics) wanted_.insert(ros::topic_key(t));
    for (const auto& t : options.topics) wanted_.insert(ros::topic_key(t));
  }

  log::Log read(McapReadStats* stats) {
    check_magic_and_header();
    std::vector<ChunkIndexRecord> chunks;
    const bool indexed = read_summary(chunks) && !chunks.empty();
    indexed_ = indexed;
    if (indexed) {
      // The file's first message: the statistics' start time, or the earliest chunk's.
      std::uint64_t first = statistics_start_.value_or(std::numeric_limits<std::uint64_t>::max());
      for (const auto& c : chunks) first = std::min(first, c.start_time);
      fix_origin(first);
      read_indexed(chunks);
    } else {
      scan();
    }
    for (const std::string& t : options_.topics) {
      const std::string topic = ros::topic_key(t);
      const bool found = std::any_of(channels_.begin(), channels_.end(),
                                     [&](const auto& c) { return ros::topic_key(c.second.topic) == topic; });
      if (!found) throw McapError{"no topic /" + topic + " in the file"};
    }
    if (stats != nullptr) {
      stats->bytes_read = file_.bytes_read();
      stats->indexed = indexed;
      stats->chunks_read = chunks_read_;
      stats->chunks_in_file = indexed ? chunks.size() : chunks_seen_;
    }
    return messages_.build(options_.mapping);
  }

 private:
  static ros::MessageLogOptions message_options(const LoadOptions& options) {
    ros::MessageLogOptions o;
    o.time = options.header_time ? ros::TimeSource::header : ros::TimeSource::record;
    o.limits.max_array = options.max_array;
    return o;
  }

  void check_magic_and_header() {
    std::vector<std::uint8_t> head;
    if (file_.size() < 8) throw McapError{"not an MCAP file (shorter than its magic bytes)"};
    file_.read(0, 8, head);
    if (std::memcmp(head.data(), kMagic, 5) != 0) throw McapError{"not an MCAP file (no MCAP magic bytes)"};
    if (head[5] != '0') throw McapError{std::string("MCAP major version '") + char(head[5]) + "'; RoverLab reads 0"};
    if (std::memcmp(head.data(), kMagic, 8) != 0) throw McapError{"not an MCAP file (damaged magic bytes)"};
    file_.read(8, 9, head);
    if (head[0] != kHeader) throw McapError{"the first record is not a Header record (opcode " + hex(head[0]) + ")"};
    // A file that does not end as an MCAP file ends (footer, magic) was cut
    // short or never finished: refused rather than read in part.
    if (file_.size() < 8 + 9 + 29 + 8) throw McapError{"truncated: too short for a header, a footer and two magics"};
    file_.read(file_.size() - 8, 8, head);
    if (std::memcmp(head.data(), kMagic, 8) != 0) {
      throw McapError{"truncated or unfinished: no MCAP magic bytes at the end of the file"};
    }
  }

  // The summary's schemas, channels and chunk indexes; false when the file
  // has no summary.
  bool read_summary(std::vector<ChunkIndexRecord>& chunks) {
    constexpr std::uint64_t kFooterRecord = 1 + 8 + 20;
    std::vector<std::uint8_t> tail;
    const std::uint64_t footer = file_.size() - 8 - kFooterRecord;
    file_.read(footer, kFooterRecord, tail);
    if (tail[0] != kFooter) throw McapError{"no Footer record before the closing magic bytes"};
    Cursor c(tail.data() + 9, 20, "Footer");
    const auto summary_start = c.number<std::uint64_t>();
    const auto summary_offset_start = c.number<std::uint64_t>();
    const auto summary_crc = c.number<std::uint32_t>();
    if (summary_start == 0) return false;
    const std::uint64_t summary_end = summary_offset_start != 0 ? summary_offset_start : footer;
    if (summary_start < 8 || summary_start > summary_end || summary_end > footer) {
      throw McapError{"the footer's summary offsets (" + std::to_string(summary_start) + ", " +
                      std::to_string(summary_offset_start) + ") lie outside the file"};
    }
    // The summary and summary offset sections, read at once: the footer's CRC
    // covers them and its own fields up to the CRC (0: none written).
    std::vector<std::uint8_t> summary;
    file_.read(summary_start, footer - summary_start, summary);
    if (summary_crc != 0) {
      const std::uint32_t crc = crc32_of(crc32_of(0, summary.data(), summary.size()), tail.data(), 1 + 8 + 16);
      if (crc != summary_crc) {
        throw McapError{"the summary section is damaged (its CRC-32 is " + crc_text(crc) + ", the footer says " +
                        crc_text(summary_crc) + ")"};
      }
    }
    summary.resize(static_cast<std::size_t>(summary_end - summary_start));
    for_each_record(summary.data(), summary.size(), summary_start,
                    [&](std::uint8_t op, const std::uint8_t* data, std::size_t size, std::uint64_t) {
                      if (op == kChunkIndex) chunks.push_back(chunk_index(data, size));
                      if (op == kStatistics) statistics(data, size);
                      if (op == kSchema || op == kChannel) definition_record(op, data, size);
                      return true;
                    });
    return true;
  }

  // Messages per channel: a whole-file read allocates each column once.
  void statistics(const std::uint8_t* data, std::size_t size) {
    Cursor c(data, size, "Statistics");
    const auto count = c.number<std::uint64_t>();                 // message count
    (void)c.number<std::uint16_t>();                              // schema count
    for (int k = 0; k < 4; ++k) (void)c.number<std::uint32_t>();  // channel, attachment, metadata, chunk counts
    const auto start = c.number<std::uint64_t>();                 // message start time
    if (count > 0) statistics_start_ = start;
    (void)c.number<std::uint64_t>();  // message end time
    const auto [map, map_size] = c.bytes<std::uint32_t>();
    Cursor m(map, map_size, "Statistics");
    for (std::size_t k = 0; k < map_size / 10; ++k) {
      const auto id = m.number<std::uint16_t>();
      message_counts_[id] = m.number<std::uint64_t>();
    }
  }

  ChunkIndexRecord chunk_index(const std::uint8_t* data, std::size_t size) const {
    Cursor c(data, size, "Chunk Index");
    ChunkIndexRecord r;
    r.start_time = c.number<std::uint64_t>();
    r.end_time = c.number<std::uint64_t>();
    r.offset = c.number<std::uint64_t>();
    r.length = c.number<std::uint64_t>();
    const auto [map, map_size] = c.bytes<std::uint32_t>();
    Cursor m(map, map_size, "Chunk Index");
    for (std::size_t k = 0; k < map_size / 10; ++k) {
      r.channels.insert(m.number<std::uint16_t>());
      (void)m.number<std::uint64_t>();
    }
    if (r.offset < 8 || r.offset > file_.size() || r.length > file_.size() - r.offset) {
      throw McapError{"a chunk index points at " + std::to_string(r.length) + " bytes at offset " +
                      std::to_string(r.offset) + ", outside the " + std::to_string(file_.size()) + "-byte file"};
    }
    return r;
  }

  bool time_overlaps(std::uint64_t start, std::uint64_t end) const {
    return !(start_ns_ && end < *start_ns_) && !(end_ns_ && start > *end_ns_);
  }

  // A time range in seconds after the file's first message (LoadOptions)
  // becomes log times once that message's time is known: from the summary,
  // or on a scan the first chunk or message met.
  void fix_origin(std::uint64_t first_ns) {
    if (!relative_ || origin_ns_ || first_ns > static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max())) {
      return;
    }
    origin_ns_ = first_ns;
    const auto at = [&](double s) { return first_ns + static_cast<std::uint64_t>(std::llround(s * 1e9)); };
    if (options_.start_s) start_ns_ = at(*options_.start_s);
    if (options_.end_s) end_ns_ = at(*options_.end_s);
    messages_.set_time_origin(static_cast<std::int64_t>(first_ns));
  }

  void read_indexed(std::vector<ChunkIndexRecord>& chunks) {
    std::sort(chunks.begin(), chunks.end(), [](const auto& a, const auto& b) { return a.offset < b.offset; });
    // Each chunk once: indexes that point into one chunk would have it decompressed again and again.
    for (std::size_t k = 1; k < chunks.size(); ++k) {
      if (chunks[k].offset < chunks[k - 1].offset + chunks[k - 1].length) {
        throw McapError{"two chunk indexes point into the chunk at offset " + std::to_string(chunks[k - 1].offset)};
      }
    }
    std::vector<std::uint8_t> record;
    for (const ChunkIndexRecord& chunk : chunks) {
      if (!time_overlaps(chunk.start_time, chunk.end_time)) continue;
      if (!wanted_.empty()) {
        bool any = false;
        for (std::uint16_t id : chunk.channels) {
          const auto it = channels_.find(id);
          any = any || (it != channels_.end() && wanted_.count(ros::topic_key(it->second.topic)) != 0);
        }
        if (!any) continue;
      }
      file_.read(chunk.offset, chunk.length, record);
      if (record.size() < 9 || record[0] != kChunk) {
        throw McapError{"a chunk index points at offset " + std::to_string(chunk.offset) +
                        ", which holds no Chunk record"};
      }
      std::uint64_t length = 0;
      std::memcpy(&length, record.data() + 1, 8);
      if (length != record.size() - 9) {
        throw McapError{"the chunk at offset " + std::to_string(chunk.offset) + " is " + std::to_string(length) +
                        " bytes long, its index says " + std::to_string(record.size() - 9)};
      }
      read_chunk(record.data() + 9, record.size() - 9);
    }
  }

  // The data section, record by record, to the Data End or Footer record.
  // Every byte before the Data End record goes through the CRC its record
  // holds (0: none written), so every record is read whole.
  void scan() {
    std::uint64_t at = 8;
    std::vector<std::uint8_t> head;
    std::vector<std::uint8_t> content;
    std::uint32_t crc = crc32_of(0, kMagic, 8);
    while (at < file_.size()) {
      if (file_.size() - at < 9)
        throw McapError{"truncated: a record header at offset " + std::to_string(at) + " is cut"};
      file_.read(at, 9, head);
      std::uint64_t length = 0;
      std::memcpy(&length, head.data() + 1, 8);
      if (length > file_.size() - at - 9) {
        throw McapError{"the record at offset " + std::to_string(at) + " (opcode " + hex(head[0]) + ") claims " +
                        std::to_string(length) + " bytes, more than the file holds (truncated?)"};
      }
      const std::uint8_t op = head[0];
      if (op == kFooter) return;
      file_.read(at + 9, length, content);
      if (op == kDataEnd) return check_data_section(crc, content);
      crc = crc32_of(crc32_of(crc, head.data(), 9), content.data(), content.size());
      if (op == kChunk || op == kSchema || op == kChannel || op == kMessage) {
        record(op, content.data(), content.size(), at);
      }
      at += 9 + length;
    }
  }

  static void check_data_section(std::uint32_t crc, const std::vector<std::uint8_t>& data_end) {
    Cursor c(data_end.data(), data_end.size(), "Data End");
    const auto expected = c.number<std::uint32_t>();
    if (expected != 0 && expected != crc) {
      throw McapError{"the data section is damaged (its CRC-32 is " + crc_text(crc) + ", the Data End record says " +
                      crc_text(expected) + ")"};
    }
  }

  template <class Visit>
  void for_each_record(const std::uint8_t* data, std::size_t size, std::uint64_t base, Visit&& visit) {
    std::size_t at = 0;
    while (at < size) {
      if (size - at < 9) {
        throw McapError{"a record header at offset " + std::to_string(base + at) + " is cut (" +
                        std::to_string(size - at) + " bytes left)"};
      }
      std::uint64_t length = 0;
      std::memcpy(&length, data + at + 1, 8);
      if (length > size - at - 9) {
        throw McapError{"the record at offset " + std::to_string(base + at) + " (opcode " + hex(data[at]) +
                        ") claims " + std::to_string(length) + " bytes, more than its section holds"};
      }
      if (!visit(data[at], data + at + 9, static_cast<std::size_t>(length), base + at)) return;
      at += 9 + static_cast<std::size_t>(length);
    }
  }

  void record(std::uint8_t op, const std::uint8_t* data, std::size_t size, std::uint64_t) {
    if (op == kChunk) {
      read_chunk(data, size);
    } else if (op == kMessage) {
      message(data, size);
    } else {
      definition_record(op, data, size);
    }
  }

  void definition_record(std::uint8_t op, const std::uint8_t* data, std::size_t size) {
    if (op == kSchema) {
      Cursor c(data, size, "Schema");
      const auto id = c.number<std::uint16_t>();
      SchemaRecord s;
      s.name = c.string();
      s.encoding = c.string();
      const auto [text, n] = c.bytes<std::uint32_t>();
      s.data.assign(reinterpret_cast<const char*>(text), n);
      schemas_.emplace(id, std::move(s));  // a repeated schema keeps its first record
    } else if (op == kChannel) {
      Cursor c(data, size, "Channel");
      const auto id = c.number<std::uint16_t>();
      ChannelRecord ch;
      ch.schema = c.number<std::uint16_t>();
      ch.topic = c.string();
      ch.message_encoding = c.string();
      channels_.emplace(id, std::move(ch));
    }
  }

  void read_chunk(const std::uint8_t* data, std::size_t size) {
    Cursor c(data, size, "Chunk");
    const auto start = c.number<std::uint64_t>();
    const auto end = c.number<std::uint64_t>();
    const auto uncompressed_size = c.number<std::uint64_t>();
    const auto chunk_crc = c.number<std::uint32_t>();  // of the uncompressed records (0: none)
    const std::string compression = c.string();
    const auto [records, n] = c.bytes<std::uint64_t>();
    ++chunks_seen_;
    fix_origin(start);
    // On a scan a chunk outside the range is still read: it may hold the
    // Schema and Channel records of later messages.
    if (indexed_ && !time_overlaps(start, end)) return;
    ++chunks_read_;
    charge_decompressed(uncompressed_size);
    const std::vector<std::uint8_t> plain = decompress(compression, records, n, uncompressed_size);
    if (chunk_crc != 0) {
      const std::uint32_t crc = crc32_of(0, plain.data(), plain.size());
      if (crc != chunk_crc) {
        throw McapError{"a chunk of messages from " + std::to_string(start) + " ns is damaged (its CRC-32 is " +
                        crc_text(crc) + ", the chunk says " + crc_text(chunk_crc) + ")"};
      }
    }
    for_each_record(plain.data(), plain.size(), 0,
                    [&](std::uint8_t op, const std::uint8_t* d, std::size_t s, std::uint64_t at) {
                      if (op == kMessage || op == kSchema || op == kChannel) record(op, d, s, at);
                      return true;
                    });
  }

  // The bytes a file may decompress to, over all its chunks: kMaxExpansion
  // times its size, at least kMinDecompressed (a 50 kB file of chunks of
  // zeros would otherwise unpack hundreds of GiB).
  void charge_decompressed(std::uint64_t bytes) {
    constexpr std::uint64_t kMaxExpansion = 1000;
    constexpr std::uint64_t kMinDecompressed = std::uint64_t{256} << 20;
    const std::uint64_t budget = std::max(kMinDecompressed, kMaxExpansion * file_.size());
    decompressed_ += std::min(bytes, budget + 1);
    if (decompressed_ > budget) {
      throw McapError{"its chunks decompress to more than " + std::to_string(budget) + " bytes (" +
                      std::to_string(kMaxExpansion) + " times the file's size, at least " +
                      std::to_string(kMinDecompressed >> 20) + " MiB: the cap on decompressed bytes)"};
    }
  }

  std::size_t topic_of(std::uint16_t id, ChannelRecord& ch) {
    if (ch.topic_index) return *ch.topic_index;
    ros::Dialect dialect = ros::Dialect::ros1;
    ros::Encoding encoding = ros::Encoding::json;
    std::string type = "json";
    std::string definition;
    const auto schema = schemas_.find(ch.schema);
    if (schema != schemas_.end()) {
      type = schema->second.name;
      definition = schema->second.data;
    }
    const std::string schema_encoding = schema != schemas_.end() ? schema->second.encoding : "";
    if (ch.message_encoding == "ros1" && schema_encoding == "ros1msg") {
      encoding = ros::Encoding::ros1;
    } else if (ch.message_encoding == "cdr" && schema_encoding == "ros2msg") {
      dialect = ros::Dialect::ros2;
      encoding = ros::Encoding::cdr;
    } else if (ch.message_encoding != "json") {
      if (ch.schema != 0 && schema == schemas_.end()) {
        throw McapError{"channel " + std::to_string(id) + " (" + ch.topic + ") names schema " +
                        std::to_string(ch.schema) + ", which no Schema record defines"};
      }
      throw McapError{"topic " + ch.topic + ": message encoding '" + ch.message_encoding + "' with schema encoding '" +
                      schema_encoding +
                      "' is not supported (RoverLab reads ros1 with ros1msg, cdr with ros2msg, json)"};
    }
    ch.topic_index = messages_.add_topic(ch.topic, type, definition, dialect, encoding);
    const auto count = message_counts_.find(id);
    const bool whole = !start_ns_ && !end_ns_ && wanted_.empty();
    // A count no file of this size could hold (a message record takes at least 31 bytes, before any
    // compression) is not believed beyond that.
    if (whole && count != message_counts_.end()) {
      messages_.expect_messages(*ch.topic_index,
                                static_cast<std::size_t>(std::min<std::uint64_t>(count->second, file_.size() / 31)));
    }
    return *ch.topic_index;
  }

  void message(const std::uint8_t* data, std::size_t size) {
    Cursor c(data, size, "Message");
    const auto id = c.number<std::uint16_t>();
    (void)c.number<std::uint32_t>();  // sequence
    const auto log_time = c.number<std::uint64_t>();
    (void)c.number<std::uint64_t>();  // publish time
    const auto [bytes, n] = c.rest();
    fix_origin(log_time);
    if (!time_overlaps(log_time, log_time)) return;
    const auto it = channels_.find(id);
    if (it == channels_.end()) {
      throw McapError{"a message on channel " + std::to_string(id) + ", which no Channel record defines"};
    }
    if (!wanted_.empty() && wanted_.count(ros::topic_key(it->second.topic)) == 0) return;
    if (log_time > static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max())) {
      throw McapError{"a message's log time " + std::to_string(log_time) + " ns is beyond the year 2262"};
    }
    messages_.add_message(topic_of(id, it->second), static_cast<std::int64_t>(log_time), bytes, n);
  }

  std::string path_;
  const LoadOptions& options_;
  File file_;
  std::set<std::string> wanted_;
  std::map<std::uint16_t, SchemaRecord> schemas_;
  std::map<std::uint16_t, ChannelRecord> channels_;
  std::map<std::uint16_t, std::uint64_t> message_counts_;  // the summary's statistics
  std::uint64_t chunks_read_ = 0;                          // chunks decompressed
  std::uint64_t chunks_seen_ = 0;                          // chunk records met on a scan
  std::uint64_t decompressed_ = 0;                         // bytes the chunks read so far unpack to
  std::optional<std::uint64_t> statistics_start_;          // the summary's first message time
  std::optional<std::uint64_t> start_ns_;                  // the log times to read
  std::optional<std::uint64_t> end_ns_;
  bool relative_ = false;  // the range is LoadOptions' seconds after the first message
  bool indexed_ = false;   // the summary's chunk indexes choose the chunks
  std::optional<std::uint64_t> origin_ns_;
  ros::MessageLog messages_;
};

class McapLogReader final : public LogReader {
 public:
  std::string name() const override { return "MCAP"; }

  Confidence can_read(const std::string& path, const LoadOptions&) const override {
    if (has_mcap_magic(path)) return Confidence::format;
    return has_extension(path, {".mcap"}) ? Confidence::extension : Confidence::none;
  }

  log::Log read(const std::string& path, const LoadOptions& options) const override { return read_mcap(path, options); }
};

}  // namespace

bool has_mcap_magic(const std::string& path) {
  std::FILE* in = std::fopen(path.c_str(), "rb");
  if (in == nullptr) return false;
  std::uint8_t head[5] = {};
  const bool found = std::fread(head, 1, 5, in) == 5 && std::memcmp(head, kMagic, 5) == 0;
  std::fclose(in);
  return found;
}

log::Log read_mcap(const std::string& path, const LoadOptions& options, const McapSelection& selection,
                   McapReadStats* stats) {
  try {
    return McapReader(path, options, selection).read(stats);
  } catch (const McapError& e) {
    throw InputError(path, e.problem);
  } catch (const std::bad_alloc&) {
    throw InputError(path, "a length in the file asks for more memory than there is");
  }
}

std::unique_ptr<LogReader> make_mcap_log_reader() { return std::make_unique<McapLogReader>(); }

}  // namespace roverlab::io
