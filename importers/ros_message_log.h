#pragma once
// Turning the messages of a ROS 1 bag or an MCAP file into a log: each topic
// one stream (named by the topic without its leading '/'), each decoded value
// one channel (ros_msg_decoder.h names them), time in seconds from the first
// message of the file. With a mapping, only the streams it names, with its
// names and units (docs/log-format.md, "ROS bags and MCAP files").

#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

#include "core/log/log.h"
#include "importers/mapping.h"
#include "importers/ros_msg_decoder.h"

namespace roverlab::io::ros {

// Which time a message gets: the time it was recorded (the bag's or MCAP's
// log time), or its header.stamp when its type starts with a std_msgs/Header
// and the stamp is set (the record time otherwise).
enum class TimeSource { record, header };

// "record" or "header"; throws DataError otherwise.
TimeSource parse_time_source(const std::string& text);

// "START:END" seconds (either may be empty: from the start, to the end);
// throws DataError unless 0 <= START <= END, both finite.
void parse_time_range(const std::string& text, std::optional<double>& start_s, std::optional<double>& end_s);

// "/imu/data" and "imu/data" alike: a topic without its leading '/'s.
std::string topic_key(const std::string& topic);

struct MessageLogOptions {
  TimeSource time = TimeSource::record;
  Limits limits;
};

class MessageLog {
 public:
  MessageLog(std::string path, MessageLogOptions options);
  ~MessageLog();
  MessageLog(const MessageLog&) = delete;
  MessageLog& operator=(const MessageLog&) = delete;

  // The topic's index; a topic seen before (another connection or channel)
  // keeps its index. Throws InputError naming the file when the definition
  // cannot be parsed or the topic changes its type. Encoding::json needs no
  // definition: each message's numbers and booleans are its values.
  std::size_t add_topic(const std::string& topic, const std::string& type, const std::string& definition,
                        Dialect dialect, Encoding encoding);

  // The number of messages a topic will get, when the file says (its index):
  // its columns are then allocated once, at their size.
  void expect_messages(std::size_t topic, std::size_t count);

  // Decodes one message. Throws InputError naming the file, topic and
  // message when it does not match its definition.
  void add_message(std::size_t topic, std::int64_t record_ns, const std::uint8_t* data, std::size_t size);

  // The topics in the order of their first messages' record times (ties in
  // the order they were added): as a reader that reads in time order adds
  // them, for one that reads a file's chunks in file order. Indexes returned
  // by add_topic are not valid after it: call it just before build().
  void order_topics_by_first_record();

  // Times count from this Unix time (ns) rather than from the first message
  // read (a time range counts from the file's first message).
  void set_time_origin(std::int64_t ns) { origin_ns_ = ns; }

  // The log: every topic, or what `mapping` names. Throws InputError. The
  // decoded columns move into the log: call it once, last.
  log::Log build(const std::optional<Mapping>& mapping);

 private:
  struct Topic;
  log::Stream mapped_stream(const StreamMapping& sm, const Topic& t, const std::string& label,
                            std::int64_t origin) const;
  static std::vector<double> seconds_of(const Topic& t, const std::vector<std::size_t>& rows, std::int64_t origin);
  template <class Where>
  void append(Topic& t, std::int64_t time_ns, const Where& where);

  // The channels a whole file may make (Limits::max_channels is a topic's).
  static constexpr std::size_t kMaxFileChannels = 200'000;

  std::string path_;
  MessageLogOptions options_;
  std::vector<std::unique_ptr<Topic>> topics_;
  std::unordered_map<std::string, std::size_t> topic_index_;  // topic name -> index in topics_
  std::size_t channels_ = 0;                                  // over every topic
  std::optional<std::int64_t> origin_ns_;
};

}  // namespace roverlab::io::ros
