// ROS 1 bags (format 2.0) as a LogReader: the rosbag library reads the file
// (chunks uncompressed, bz2 or lz4); each connection's message definition
// drives a generic decoder (importers/ros_message_log.h).
#include <climits>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <map>
#include <new>
#include <optional>
#include <set>
#include <unordered_map>

#include <console_bridge/console.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>

#include "core/common/error.h"
#include "importers/log_reader.h"
#include "importers/ros_message_log.h"

namespace roverlab::io {
namespace {
// A message's serialized bytes where the library holds them (its chunk
// buffer), valid until the next message is read: "instantiated" through the
// library's own path, which parses the record header once (size() and
// write() parse it twice) and copies nothing.
struct BagBytes {
  const std::uint8_t* data = nullptr;
  std::uint32_t size = 0;
};
}  // namespace
}  // namespace roverlab::io

namespace ros {
namespace message_traits {
template <>
struct MD5Sum<roverlab::io::BagBytes> {
  static const char* value() { return "*"; }  // any type
  static const char* value(const roverlab::io::BagBytes&) { return value(); }
};
template <>
struct DataType<roverlab::io::BagBytes> {
  static const char* value() { return "*"; }
  static const char* value(const roverlab::io::BagBytes&) { return value(); }
};
}  // namespace message_traits
namespace serialization {
template <>
struct Serializer<roverlab::io::BagBytes> {
  template <typename Stream>
  static void read(Stream& stream, roverlab::io::BagBytes& m) {
    m.data = stream.getData();
    m.size = stream.getLength();
  }
};
}  // namespace serialization
}  // namespace ros

namespace roverlab::io {

namespace {

constexpr char kMagic[] = "#ROSBAG V";

// The version line ("2.0"), or empty when the file does not start as a bag.
std::string bag_version(const std::string& path) {
  std::FILE* in = std::fopen(path.c_str(), "rb");
  if (in == nullptr) return {};
  char head[16] = {};
  const std::size_t got = std::fread(head, 1, sizeof head - 1, in);
  std::fclose(in);
  const std::size_t magic = sizeof kMagic - 1;
  if (got < magic || std::memcmp(head, kMagic, magic) != 0) return {};
  std::string version(head + magic, got - magic);
  const std::size_t end = version.find('\n');
  return end == std::string::npos ? "?" : version.substr(0, end);
}

// Messages per connection id, from the bag's chunk info records (format 2.0:
// the file header's index_pos, then conn_count connection records and
// chunk_count chunk info records, each chunk's counts per connection): a few
// kilobytes read, where the library's View::size() walks every index entry.
// Empty when the records are not as expected (the caller then asks the library).
class ChunkInfoCounts {
 public:
  explicit ChunkInfoCounts(const std::string& path) : in_(std::fopen(path.c_str(), "rb")) {}
  ~ChunkInfoCounts() {
    if (in_ != nullptr) std::fclose(in_);
  }
  ChunkInfoCounts(const ChunkInfoCounts&) = delete;
  ChunkInfoCounts& operator=(const ChunkInfoCounts&) = delete;

  std::map<std::uint32_t, std::uint64_t> counts() {
    std::map<std::uint32_t, std::uint64_t> out;
    std::uint64_t total = 0;
    if (in_ == nullptr || std::fseek(in_, 13, SEEK_SET) != 0) return {};  // after "#ROSBAG V2.0\n"
    std::map<std::string, std::string> fields;
    if (!record(fields) || fields["op"] != std::string(1, '\x03')) return {};
    const auto index_pos = number<std::uint64_t>(fields["index_pos"]);
    const auto connections = number<std::uint32_t>(fields["conn_count"]);
    const auto chunks = number<std::uint32_t>(fields["chunk_count"]);
    if (!index_pos || !connections || !chunks || *index_pos > static_cast<std::uint64_t>(LONG_MAX) ||
        std::fseek(in_, static_cast<long>(*index_pos), SEEK_SET) != 0) {
      return {};
    }
    for (std::uint32_t k = 0; k < *connections; ++k) {
      if (!record(fields) || fields["op"] != std::string(1, '\x07')) return {};
    }
    for (std::uint32_t k = 0; k < *chunks; ++k) {
      if (!record(fields) || fields["op"] != std::string(1, '\x06')) return {};
      const auto n = number<std::uint32_t>(fields["count"]);
      if (!n || data_.size() != std::size_t{8} * *n) return {};
      for (std::uint32_t e = 0; e < *n; ++e) {
        std::uint32_t pair[2];
        std::memcpy(pair, data_.data() + 8 * e, 8);
        out[pair[0]] += pair[1];
        total += pair[1];
      }
    }
    // A message record takes more than 40 bytes: counts the file could not hold are not believed.
    if (std::fseek(in_, 0, SEEK_END) != 0 || std::ftell(in_) < 0 ||
        total > static_cast<std::uint64_t>(std::ftell(in_)) / 40) {
      return {};
    }
    return out;
  }

 private:
  template <class T>
  static std::optional<T> number(const std::string& bytes) {
    if (bytes.size() != sizeof(T)) return std::nullopt;
    T v;
    std::memcpy(&v, bytes.data(), sizeof v);
    return v;
  }

  // One record: its header's fields, its data in data_.
  bool record(std::map<std::string, std::string>& fields) {
    fields.clear();
    std::string header;
    if (!block(header)) return false;
    std::size_t at = 0;
    while (at + 4 <= header.size()) {
      std::uint32_t n = 0;
      std::memcpy(&n, header.data() + at, 4);
      at += 4;
      if (n > header.size() - at) return false;
      const std::string field = header.substr(at, n);
      at += n;
      const std::size_t eq = field.find('=');
      if (eq == std::string::npos) return false;
      fields[field.substr(0, eq)] = field.substr(eq + 1);
    }
    return at == header.size() && block(data_);
  }

  // A uint32 length and that many bytes (at most 64 MiB: an index record is small).
  bool block(std::string& out) {
    std::uint32_t n = 0;
    if (std::fread(&n, 4, 1, in_) != 1 || n > (1U << 26)) return false;
    out.resize(n);
    return n == 0 || std::fread(out.data(), 1, n, in_) == n;
  }

  std::FILE* in_;
  std::string data_;
};

class Ros1BagReader final : public LogReader {
 public:
  std::string name() const override { return "ROS 1 bag"; }

  Confidence can_read(const std::string& path, const LoadOptions&) const override {
    if (!bag_version(path).empty()) return Confidence::format;
    return has_extension(path, {".bag"}) ? Confidence::extension : Confidence::none;
  }

  std::pair<std::string, std::string> crash_guard_names() const override { return {"ROS bag", "rosbag library"}; }

  log::Log read(const std::string& path, const LoadOptions& options) const override {
    ros::MessageLogOptions message_options;
    message_options.time = options.header_time ? ros::TimeSource::header : ros::TimeSource::record;
    message_options.limits.max_array = options.max_array;
    ros::MessageLog messages(path, message_options);
    std::unordered_map<const void*, std::size_t> topic_of;  // by connection (its topic's address)
    std::unordered_map<std::string, std::size_t> counts;    // messages per topic, from the bag's index
    each_message(
        path, options,
        [&](rosbag::Bag& bag, const Range& range) {
          // A whole bag: its chunk infos' counts; a time range (or an index not as
          // expected): the library's count of the view.
          const auto by_connection =
              range.relative ? std::map<std::uint32_t, std::uint64_t>{} : ChunkInfoCounts(path).counts();
          rosbag::View all(bag);
          for (const rosbag::ConnectionInfo* c : all.getConnections()) {
            if (!by_connection.empty()) {
              const auto it = by_connection.find(c->id);
              counts[c->topic] += it != by_connection.end() ? it->second : 0;
            } else if (counts.count(c->topic) == 0) {
              counts[c->topic] = rosbag::View(bag, rosbag::TopicQuery(c->topic), range.start, range.end).size();
            }
          }
          if (range.relative) messages.set_time_origin(static_cast<std::int64_t>(range.origin.toNSec()));
        },
        [&](const rosbag::MessageInstance& m, const BagBytes& bytes) {
          // The connection's topic string (in its ConnectionInfo) stands for the connection:
          // no shared_ptr copied per message, as getConnectionHeader() would.
          const void* connection = &m.getTopic();
          auto it = topic_of.find(connection);
          if (it == topic_of.end()) {
            const std::size_t topic = messages.add_topic(m.getTopic(), m.getDataType(), m.getMessageDefinition(),
                                                         ros::Dialect::ros1, ros::Encoding::ros1);
            messages.expect_messages(topic, counts[m.getTopic()]);
            it = topic_of.emplace(connection, topic).first;
          }
          messages.add_message(it->second, static_cast<std::int64_t>(m.getTime().toNSec()), bytes.data, bytes.size);
        });
    return messages.build(options.mapping);
  }

  // The crash guard's trial: the library's calls on every message, no decoding.
  void trial_read(const std::string& path, const LoadOptions&) const override {
    each_message(
        path, {}, [](rosbag::Bag&, const Range&) {}, [](const rosbag::MessageInstance&, const BagBytes&) {});
  }

 private:
  // The record times to read: a range in seconds after the bag's first message.
  struct Range {
    ::ros::Time start = ::ros::TIME_MIN;
    ::ros::Time end = ::ros::TIME_MAX;
    ::ros::Time origin;
    bool relative = false;
  };

  static Range range_of(rosbag::Bag& bag, const LoadOptions& options) {
    Range r;
    if (!options.start_s && !options.end_s) return r;
    r.relative = true;
    r.origin = rosbag::View(bag).getBeginTime();
    const auto at = [&](double seconds) {
      ::ros::Time t;
      t.fromNSec(r.origin.toNSec() + static_cast<std::uint64_t>(std::llround(seconds * 1e9)));
      return t;
    };
    if (options.start_s) r.start = at(*options.start_s);
    if (options.end_s) r.end = at(*options.end_s);
    return r;
  }

  // Calls opened(the bag, the range read), then visit(message, its bytes) for
  // every message of the bag that `options` selects (topics, time range), in
  // time order.
  template <class Opened, class Visit>
  static void each_message(const std::string& path, const LoadOptions& options, Opened&& opened, Visit&& visit) {
    const std::string version = bag_version(path);
    if (version.empty()) throw InputError(path, "not a ROS bag (no '#ROSBAG V2.0' line at the start)");
    if (version != "2.0") throw InputError(path, "ROS bag version " + version + "; RoverLab reads version 2.0");
    // The library's own log lines are not RoverLab's one line.
    console_bridge::setLogLevel(console_bridge::CONSOLE_BRIDGE_LOG_NONE);
    try {
      rosbag::Bag bag;
      bag.open(path, rosbag::bagmode::Read);
      std::set<std::string> wanted;
      for (const auto& t : options.topics) wanted.insert(ros::topic_key(t));
      std::set<std::string> found;
      for (const rosbag::ConnectionInfo* c : rosbag::View(bag).getConnections()) found.insert(ros::topic_key(c->topic));
      for (const auto& t : wanted) {
        if (found.count(t) == 0) throw InputError(path, "no topic /" + t + " in the file");
      }
      const Range range = range_of(bag, options);
      opened(bag, range);
      rosbag::View view(
          bag,
          [&](const rosbag::ConnectionInfo* c) {
            return wanted.empty() || wanted.count(ros::topic_key(c->topic)) != 0;
          },
          range.start, range.end);
      for (const rosbag::MessageInstance& m : view) {
        const boost::shared_ptr<BagBytes> bytes = m.instantiate<BagBytes>();
        if (!bytes) throw InputError(path, "corrupt ROS bag: a message could not be read");
        visit(m, *bytes);
      }
    } catch (const InputError&) {
      throw;
    } catch (const std::bad_alloc&) {
      throw InputError(path, "corrupt ROS bag: a length in the file asks for more memory than there is");
    } catch (const std::exception& e) {
      throw InputError(path, std::string("corrupt or unreadable ROS bag: ") + e.what());
    }
  }
};

}  // namespace

std::unique_ptr<LogReader> make_ros1_bag_log_reader() { return std::make_unique<Ros1BagReader>(); }

}  // namespace roverlab::io
