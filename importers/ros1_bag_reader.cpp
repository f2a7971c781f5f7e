// ROS 1 bags (format 2.0) as a LogReader: the rosbag library opens the file
// (its index and connections) and decompresses its chunks (bz2, lz4), whose
// records are read by importers/ros1_bag_chunks.h; each connection's message
// definition drives a generic decoder (importers/ros_message_log.h).
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
#include "importers/crash_guard.h"
#include "importers/log_reader.h"
#include "importers/ros1_bag_chunks.h"
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

class Ros1BagReader final : public LogReader {
 public:
  std::string name() const override { return "ROS 1 bag"; }

  Confidence can_read(const std::string& path, const LoadOptions&) const override {
    if (!bag_version(path).empty()) return Confidence::format;
    return has_extension(path, {".bag"}) ? Confidence::extension : Confidence::none;
  }

  std::pair<std::string, std::string> crash_guard_names() const override { return {"ROS bag", "rosbag library"}; }

  // The chunks read record by record (importers/ros1_bag_chunks.h); through
  // the library's View when the index is not as expected, the bag is
  // encrypted, or a topic's record times go back in the file (the View hands
  // out each topic's messages in time order; the chunks' order is the file's).
  log::Log read(const std::string& path, const LoadOptions& options) const override {
    std::optional<log::Log> lg = guarded(path, [&] { return read_chunks(path, options); });
    if (lg) return std::move(*lg);
    // The View's per-message path, which the crash guard's trial ran only if
    // the index was the reason: under the guard again before it runs here.
    survive_crash(
        path, [&] { view_trial(path, options); }, "ROS bag", "rosbag library");
    return guarded(path, [&] { return read_view(path, options); });
  }

  // The crash guard's trial: the library calls read() makes (opening the
  // bag, decompressing each compressed chunk; or every message through the
  // View), no decoding. An uncompressed chunk is left to the parent: reading
  // it is a plain read, and the record loop checks every length it meets.
  void trial_read(const std::string& path, const LoadOptions& options) const override {
    guarded(path, [&] {
      if (!each_chunk_message(
              path, {}, [](const Opened&) {}, [](Connection&, const rosbag_chunks::Message&) { return true; }, true)) {
        view_trial(path, options);
      }
      return 0;
    });
  }

  // The library's calls on every message through the View, no decoding.
  // The View's trial is the very read that follows it (its queries, each
  // message's definition and bytes): a trial that only walked the messages
  // let a bag whose index points past its chunks (probe 3's
  // indexdata_off_past.bag) crash the reading process about one run in five,
  // the library reading what lay past the chunk.
  static void view_trial(const std::string& path, const LoadOptions& options) {
    guarded(path, [&] { return read_view(path, options); });
  }

 private:
  // The record times to read: a range in seconds after the bag's first message.
  struct Range {
    ::ros::Time start = ::ros::TIME_MIN;
    ::ros::Time end = ::ros::TIME_MAX;
    ::ros::Time origin;
    bool relative = false;
  };

  // A connection of the bag, as the chunk loop meets its messages.
  struct Connection {
    const rosbag::ConnectionInfo* info = nullptr;
    bool wanted = true;
    std::size_t topic = SIZE_MAX;  // in the MessageLog, once its first message is read
  };

  // What the chunk loop tells its caller once the bag is open.
  struct Opened {
    rosbag::Bag& bag;
    const rosbag_chunks::BagIndex& index;
    const Range& range;
  };

  static ros::MessageLogOptions message_options(const LoadOptions& options) {
    ros::MessageLogOptions o;
    o.time = options.header_time ? ros::TimeSource::header : ros::TimeSource::record;
    o.limits.max_array = options.max_array;
    return o;
  }

  // The library's and the chunk loop's exceptions as one line naming the file.
  template <class Read>
  static auto guarded(const std::string& path, Read&& read) -> decltype(read()) {
    const std::string version = bag_version(path);
    if (version.empty()) throw InputError(path, "not a ROS bag (no '#ROSBAG V2.0' line at the start)");
    if (version != "2.0") throw InputError(path, "ROS bag version " + version + "; RoverLab reads version 2.0");
    // The library's own log lines are not RoverLab's one line.
    console_bridge::setLogLevel(console_bridge::CONSOLE_BRIDGE_LOG_NONE);
    try {
      return read();
    } catch (const InputError&) {
      throw;
    } catch (const rosbag_chunks::FormatError& e) {
      throw InputError(path, std::string("corrupt ROS bag: ") + e.what());
    } catch (const std::bad_alloc&) {
      throw InputError(path, "corrupt ROS bag: a length in the file asks for more memory than there is");
    } catch (const std::exception& e) {
      throw InputError(path, std::string("corrupt or unreadable ROS bag: ") + e.what());
    }
  }

  static std::optional<log::Log> read_chunks(const std::string& path, const LoadOptions& options) {
    ros::MessageLog messages(path, message_options(options));
    std::unordered_map<std::string, std::size_t> counts;  // messages per topic
    std::vector<std::int64_t> last_ns;                    // per topic: its latest record time so far
    const bool read = each_chunk_message(
        path, options,
        [&](const Opened& o) {
          // A whole bag: its chunk infos' counts; a time range: the library's count of the view.
          for (const rosbag::ConnectionInfo* c : rosbag::View(o.bag).getConnections()) {
            if (!o.range.relative) {
              const auto it = o.index.messages.find(c->id);
              counts[c->topic] += it != o.index.messages.end() ? it->second : 0;
            } else if (counts.count(c->topic) == 0) {
              counts[c->topic] = rosbag::View(o.bag, rosbag::TopicQuery(c->topic), o.range.start, o.range.end).size();
            }
          }
          if (o.range.relative) messages.set_time_origin(static_cast<std::int64_t>(o.range.origin.toNSec()));
        },
        [&](Connection& c, const rosbag_chunks::Message& m) {
          if (c.topic == SIZE_MAX) {
            c.topic = messages.add_topic(c.info->topic, c.info->datatype, c.info->msg_def, ros::Dialect::ros1,
                                         ros::Encoding::ros1);
            if (c.topic >= last_ns.size()) {
              last_ns.resize(c.topic + 1, INT64_MIN);
              messages.expect_messages(c.topic, counts[c.info->topic]);
            }
          }
          const std::int64_t t = m.time_ns();
          if (t < last_ns[c.topic]) return false;  // not in time order: the View's order is needed
          last_ns[c.topic] = t;
          messages.add_message(c.topic, t, m.data, m.size);
          return true;
        });
    if (!read) return std::nullopt;
    messages.order_topics_by_first_record();  // as the View meets them
    return messages.build(options.mapping);
  }

  static log::Log read_view(const std::string& path, const LoadOptions& options) {
    ros::MessageLog messages(path, message_options(options));
    std::unordered_map<const void*, std::size_t> topic_of;  // by connection (its topic's address)
    std::unordered_map<std::string, std::size_t> counts;    // messages per topic, from the bag's index
    each_message(
        path, options,
        [&](rosbag::Bag& bag, const Range& range) {
          for (const rosbag::ConnectionInfo* c : rosbag::View(bag).getConnections()) {
            if (counts.count(c->topic) == 0) {
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

  // The topics `options` names ("imu" and "/imu" alike; all when none), each
  // checked against the bag's connections.
  static std::set<std::string> wanted_topics(rosbag::Bag& bag, const std::string& path, const LoadOptions& options) {
    std::set<std::string> wanted;
    for (const auto& t : options.topics) wanted.insert(ros::topic_key(t));
    std::set<std::string> found;
    for (const rosbag::ConnectionInfo* c : rosbag::View(bag).getConnections()) found.insert(ros::topic_key(c->topic));
    for (const auto& t : wanted) {
      if (found.count(t) == 0) throw InputError(path, "no topic /" + t + " in the file");
    }
    return wanted;
  }

  // Calls opened(Opened), then visit(its connection, message) for every
  // message of the chunks that `options` selects (topics, time range), in
  // file order, until visit returns false. The library opens the bag (reads
  // and checks its index and connections); the chunks are read by
  // rosbag_chunks::ChunkReader. False when visit stopped, or when the index
  // is not as the chunk loop needs it (nothing is then visited).
  // `library_calls_only`: an uncompressed chunk's records are not read.
  template <class Open, class Visit>
  static bool each_chunk_message(const std::string& path, const LoadOptions& options, Open&& opened, Visit&& visit,
                                 bool library_calls_only = false) {
    const std::optional<rosbag_chunks::BagIndex> index = rosbag_chunks::read_index(path);
    if (!index) return false;
    rosbag::Bag bag;
    bag.open(path, rosbag::bagmode::Read);
    const std::set<std::string> wanted = wanted_topics(bag, path, options);
    const Range range = range_of(bag, options);
    std::unordered_map<std::uint32_t, Connection> connections;
    for (const rosbag::ConnectionInfo* c : rosbag::View(bag).getConnections()) {
      connections[c->id] = {c, wanted.empty() || wanted.count(ros::topic_key(c->topic)) != 0};
    }
    opened(Opened{bag, *index, range});
    const std::uint64_t start = range.start.toNSec();
    const std::uint64_t end = range.end.toNSec();
    rosbag_chunks::ChunkReader reader(path);
    rosbag_chunks::Message m;
    std::map<std::uint32_t, std::uint64_t> read;  // messages per connection
    for (const rosbag_chunks::ChunkInfo& chunk : index->chunks) {
      if (chunk.end_ns < start || chunk.start_ns > end) continue;
      reader.load(chunk.position, library_calls_only);
      while (reader.next(m)) {
        ++read[m.connection];
        const auto it = connections.find(m.connection);
        if (it == connections.end()) {
          throw rosbag_chunks::FormatError("a message of connection " + std::to_string(m.connection) +
                                           ", which the bag's index does not list");
        }
        const auto t = static_cast<std::uint64_t>(m.time_ns());
        // The library's index leaves out messages at time 0 (before ros::TIME_MIN).
        if (!it->second.wanted || t < start || t > end || t == 0) continue;
        if (!visit(it->second, m)) return false;
      }
    }
    if (!range.relative && !library_calls_only) check_counts(index->messages, read, connections);
    return true;
  }

  // Every chunk read: as many messages of each connection as the chunk infos count (records
  // damaged into other kinds, or chunks the file header leaves out, would be read as fewer).
  static void check_counts(const std::map<std::uint32_t, std::uint64_t>& counted,
                           std::map<std::uint32_t, std::uint64_t>& read,
                           const std::unordered_map<std::uint32_t, Connection>& connections) {
    for (const auto& [id, n] : counted) {
      if (read[id] >= n) continue;
      const auto c = connections.find(id);
      throw rosbag_chunks::FormatError("the index counts " + std::to_string(n) + " messages of connection " +
                                       std::to_string(id) +
                                       (c != connections.end() ? " (" + c->second.info->topic + ")" : std::string()) +
                                       ", its chunks hold " + std::to_string(read[id]));
    }
  }

  // Calls opened(the bag, the range read), then visit(message, its bytes) for
  // every message of the bag that `options` selects (topics, time range), in
  // time order, through the library's View.
  template <class Opened, class Visit>
  static void each_message(const std::string& path, const LoadOptions& options, Opened&& opened, Visit&& visit) {
    rosbag::Bag bag;
    bag.open(path, rosbag::bagmode::Read);
    const std::set<std::string> wanted = wanted_topics(bag, path, options);
    const Range range = range_of(bag, options);
    opened(bag, range);
    rosbag::View view(
        bag,
        [&](const rosbag::ConnectionInfo* c) { return wanted.empty() || wanted.count(ros::topic_key(c->topic)) != 0; },
        range.start, range.end);
    for (const rosbag::MessageInstance& m : view) {
      const boost::shared_ptr<BagBytes> bytes = m.instantiate<BagBytes>();
      if (!bytes) throw InputError(path, "corrupt ROS bag: a message could not be read");
      visit(m, *bytes);
    }
  }
};

}  // namespace

std::unique_ptr<LogReader> make_ros1_bag_log_reader() { return std::make_unique<Ros1BagReader>(); }

}  // namespace roverlab::io
