#include "importers/ros_message_log.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <limits>
#include <numeric>
#include <unordered_map>
#include <unordered_set>

#include <nlohmann/json.hpp>

#include "core/common/error.h"
#include "core/log/units.h"
#include "importers/ros_standard_units.h"

namespace roverlab::io::ros {

namespace {

// A JSON message's values nested deeper than this are not channels.
constexpr int kMaxJsonDepth = 64;

// "/imu/data" -> "imu/data" (and "a//b" -> "a/b"): a RoverLab stream name.
std::string stream_name(const std::string& topic) {
  std::string out;
  for (char c : topic) {
    if (c == '/' && (out.empty() || out.back() == '/')) continue;
    out += c;
  }
  while (!out.empty() && out.back() == '/') out.pop_back();
  return out;
}

// Unix nanoseconds as seconds with nine decimals, exactly.
std::string seconds_text(std::int64_t ns) {
  char text[64];
  std::snprintf(text, sizeof text, "%s%lld.%09lld", ns < 0 ? "-" : "",
                static_cast<long long>(std::llabs(ns / 1'000'000'000)),
                static_cast<long long>(std::llabs(ns % 1'000'000'000)));
  return text;
}

}  // namespace

void parse_time_range(const std::string& text, std::optional<double>& start_s, std::optional<double>& end_s) {
  const auto colon = text.find(':');
  const auto number = [&](const std::string& part) -> std::optional<double> {
    if (part.empty()) return std::nullopt;
    char* end = nullptr;
    const double v = std::strtod(part.c_str(), &end);
    if (end != part.c_str() + part.size() || !std::isfinite(v) || v < 0 || v > 1e9) {
      throw DataError("time range '" + text + "': '" + part + "' is not a number of seconds from 0 to 1e9");
    }
    return v;
  };
  if (colon == std::string::npos) throw DataError("time range '" + text + "' is not START:END (seconds)");
  start_s = number(text.substr(0, colon));
  end_s = number(text.substr(colon + 1));
  if (start_s && end_s && *end_s < *start_s) throw DataError("time range '" + text + "' ends before it starts");
}

std::string topic_key(const std::string& topic) { return stream_name(topic); }

TimeSource parse_time_source(const std::string& text) {
  if (text == "record") return TimeSource::record;
  if (text == "header") return TimeSource::header;
  throw DataError("time source must be 'record' or 'header', not '" + text + "'");
}

struct MessageLog::Topic {
  Topic(std::string topic, std::string type_name, std::unique_ptr<Decoder> d)
      : name(std::move(topic)), type(std::move(type_name)), decoder(std::move(d)) {}

  std::string name;
  std::string type;
  std::string definition;
  std::unique_ptr<Decoder> decoder;  // null for JSON messages
  std::vector<std::int64_t> time_ns;
  std::vector<std::string> channel_names;
  std::vector<std::vector<double>> columns;
  std::unordered_map<std::string, std::size_t> index;
  // The previous message's shape and where its values go.
  bool has_layout = false;
  std::vector<std::uint32_t> layout_lengths;
  std::vector<std::string> layout_labels;  // JSON: the value names themselves
  std::vector<std::size_t> layout;
  DecodedMessage scratch;
  std::size_t expected = 0;  // messages the file's index announces (0: unknown)
  std::size_t values_read = 0;
  std::int64_t first_record_ns = std::numeric_limits<std::int64_t>::max();

  // The column of each value of a message named `names`. A name given twice
  // (a JointState naming a joint twice, JSON keys "q/" and "q_") gets "~k",
  // with k chosen so that it equals no other name of the message.
  void relayout(const std::vector<std::string>& names, std::size_t max_channels) {
    layout.clear();
    std::unordered_set<std::string> taken(names.begin(), names.end());
    std::unordered_map<std::string, int> copies;
    for (const std::string& label : names) {
      std::string name = label;
      int& k = copies[label];
      if (++k > 1) {
        do {
          name = label + "~" + std::to_string(k++);
        } while (taken.count(name) != 0);
        --k;
        taken.insert(name);
      }
      auto it = index.find(name);
      if (it == index.end()) {
        if (columns.size() >= max_channels) {
          throw DataError("more than " + std::to_string(max_channels) + " channels (the cap on a topic's channels)");
        }
        it = index.emplace(name, columns.size()).first;
        channel_names.push_back(name);
        columns.emplace_back(time_ns.size(), std::nan(""));  // earlier messages lacked it
        if (expected > time_ns.size()) columns.back().reserve(expected);
      }
      layout.push_back(it->second);
    }
    layout_lengths = scratch.lengths;
    if (!decoder) layout_labels = scratch.labels;  // a decoder says when its labels change
    has_layout = true;
  }

  // Appends scratch: values named by the decoder, or by scratch.labels (JSON).
  void append(std::int64_t t, std::size_t max_channels) {
    const bool labels_changed = decoder ? scratch.labels_changed : scratch.labels != layout_labels;
    if (!has_layout || labels_changed || scratch.lengths != layout_lengths || scratch.values.size() != layout.size()) {
      relayout(decoder ? decoder->value_names(scratch) : scratch.labels, max_channels);
    }
    check_sparseness();
    time_ns.push_back(t);
    values_read += scratch.values.size();
    if (layout.size() == columns.size()) {  // every channel present (and each once): the common case
      for (std::size_t i = 0; i < layout.size(); ++i) columns[layout[i]].push_back(scratch.values[i]);
      return;
    }
    for (auto& c : columns) c.push_back(std::nan(""));
    for (std::size_t i = 0; i < layout.size(); ++i) columns[layout[i]].back() = scratch.values[i];
  }

  // Channels that come and go (a new joint name in every message) fill every
  // other message with NaN: the columns may hold at most kSparseness times
  // the values read (plus 128 MB), or memory grows as messages x channels.
  // (A /tf topic of 50 frames sent one by one fills 1 cell in 50.)
  void check_sparseness() const {
    constexpr std::size_t kSparseness = 64;
    const std::size_t cells = columns.size() * (time_ns.size() + 1);
    if (cells > kSparseness * (values_read + scratch.values.size()) + (std::size_t{1} << 24)) {
      throw DataError(std::to_string(columns.size()) + " channels over " + std::to_string(time_ns.size() + 1) +
                      " messages, most of them missing from most messages (more than " + std::to_string(kSparseness) +
                      " cells a value read)");
    }
  }

  // Rows in time order, one per distinct time (the first message of a time).
  std::vector<std::size_t> rows() const {
    std::vector<std::size_t> order(time_ns.size());
    std::iota(order.begin(), order.end(), std::size_t{0});
    if (!std::is_sorted(time_ns.begin(), time_ns.end())) {
      std::stable_sort(order.begin(), order.end(),
                       [&](std::size_t a, std::size_t b) { return time_ns[a] < time_ns[b]; });
    }
    std::vector<std::size_t> out;
    out.reserve(order.size());
    for (std::size_t r : order) {
      if (out.empty() || time_ns[r] != time_ns[out.back()]) out.push_back(r);
    }
    return out;
  }
};

MessageLog::MessageLog(std::string path, MessageLogOptions options) : path_(std::move(path)), options_(options) {}

MessageLog::~MessageLog() = default;

std::size_t MessageLog::add_topic(const std::string& topic, const std::string& type, const std::string& definition,
                                  Dialect dialect, Encoding encoding) {
  const auto known = topic_index_.find(topic);
  if (known != topic_index_.end()) {
    const Topic& t = *topics_[known->second];
    if (t.type != type) {
      throw InputError(path_, "topic " + topic + " carries two message types, " + t.type + " and " + type);
    }
    // Two definitions under one name (two md5sums): each connection's messages
    // would be decoded with the first one's fields.
    if (t.definition != definition) {
      throw InputError(path_, "topic " + topic + " carries two different definitions of " + type);
    }
    return known->second;
  }
  if (stream_name(topic).empty() || !log::is_valid_stream_name(stream_name(topic))) {
    throw InputError(path_, "topic name '" + topic + "' cannot name a stream");
  }
  std::unique_ptr<Decoder> decoder;
  if (encoding != Encoding::json) {
    try {
      decoder = std::make_unique<Decoder>(parse_definition(type, definition, dialect), encoding, options_.limits);
    } catch (const DefinitionError& e) {
      throw InputError(path_, "topic " + topic + ": the definition of " + type + ": " + e.what());
    }
  }
  topics_.push_back(std::make_unique<Topic>(topic, type, std::move(decoder)));
  topics_.back()->definition = definition;
  topic_index_.emplace(topic, topics_.size() - 1);
  return topics_.size() - 1;
}

namespace {

// The numbers and booleans of a JSON message, named as decoded fields are.
void flatten(const nlohmann::json& j, const std::string& name, std::size_t max_array, DecodedMessage& out,
             int depth = 0) {
  if (depth > kMaxJsonDepth) return;  // deeper values are not channels (and the stack stays bounded)
  // Past a topic's cap on channels the message is refused anyway (relayout): no need to name them all.
  if (out.values.size() > Limits{}.max_channels) return;
  if (j.is_number()) {
    out.values.push_back(j.get<double>());
    out.labels.push_back(name);
  } else if (j.is_boolean()) {
    out.values.push_back(j.get<bool>() ? 1.0 : 0.0);
    out.labels.push_back(name);
  } else if (j.is_object()) {
    for (auto it = j.begin(); it != j.end(); ++it) {
      std::string key = it.key();
      for (char& c : key) {
        if (c == '/' || c == '\0' || c == '\n' || c == '\r') c = '_';
      }
      if (key.empty()) key = "_";
      flatten(it.value(), name.empty() ? key : name + "." + key, max_array, out, depth + 1);
    }
  } else if (j.is_array() && j.size() <= max_array) {
    for (std::size_t i = 0; i < j.size(); ++i) {
      flatten(j[i], name.empty() ? std::to_string(i) : name + "." + std::to_string(i), max_array, out, depth + 1);
    }
  }
}

}  // namespace

void MessageLog::expect_messages(std::size_t topic, std::size_t count) {
  Topic& t = *topics_.at(topic);
  // An index may lie: never more than 2^28 samples reserved on its word.
  t.expected = std::min(count, std::size_t{1} << 28);
  if (t.expected > t.time_ns.size()) t.time_ns.reserve(t.expected);
}

void MessageLog::add_message(std::size_t topic, std::int64_t record_ns, const std::uint8_t* data, std::size_t size) {
  Topic& t = *topics_.at(topic);
  if (t.time_ns.empty()) t.first_record_ns = std::min(t.first_record_ns, record_ns);
  const auto where = [&] {
    return "topic " + t.name + ", message " + std::to_string(t.time_ns.size() + 1) + " (" + t.type + "): ";
  };
  if (!t.decoder) {
    t.scratch.values.clear();
    t.scratch.labels.clear();
    t.scratch.header_stamp_ns = -1;
    // Containers nested deeper than flatten reads are dropped as they are
    // parsed, not built (100,000 levels in 200 kB of text: 2 s under ASan).
    const auto shallow = [](int depth, nlohmann::json::parse_event_t event, nlohmann::json&) {
      return depth <= kMaxJsonDepth || (event != nlohmann::json::parse_event_t::object_start &&
                                        event != nlohmann::json::parse_event_t::array_start);
    };
    const nlohmann::json j = nlohmann::json::parse(data, data + size, shallow, false);
    if (j.is_discarded()) throw InputError(path_, where() + "not valid JSON");
    flatten(j, "", options_.limits.max_array, t.scratch);
    append(t, record_ns, where);
    return;
  }
  try {
    t.decoder->decode(data, size, t.scratch);
  } catch (const DecodeError& e) {
    throw InputError(path_, where() + e.what());
  }
  const bool stamped = options_.time == TimeSource::header && t.scratch.header_stamp_ns > 0;
  append(t, stamped ? t.scratch.header_stamp_ns : record_ns, where);
}

// Topic::append with the caps: a topic's channels, the file's channels.
template <class Where>
void MessageLog::append(Topic& t, std::int64_t time_ns, const Where& where) {
  const std::size_t before = t.columns.size();
  try {
    t.append(time_ns, options_.limits.max_channels);
  } catch (const DataError& e) {
    throw InputError(path_, where() + e.what());
  }
  channels_ += t.columns.size() - before;
  if (channels_ > kMaxFileChannels) {
    throw InputError(path_, where() + "more than " + std::to_string(kMaxFileChannels) +
                                " channels in the file (the cap on a file's channels)");
  }
}

void MessageLog::order_topics_by_first_record() {
  std::stable_sort(topics_.begin(), topics_.end(),
                   [](const std::unique_ptr<Topic>& a, const std::unique_ptr<Topic>& b) {
                     return a->first_record_ns < b->first_record_ns;
                   });
  topic_index_.clear();
  for (std::size_t i = 0; i < topics_.size(); ++i) topic_index_.emplace(topics_[i]->name, i);
}

namespace {

// values[rows[0]], values[rows[1]], ...
std::vector<double> picked(const std::vector<double>& values, const std::vector<std::size_t>& rows) {
  std::vector<double> out(rows.size());
  for (std::size_t i = 0; i < rows.size(); ++i) out[i] = values[rows[i]];
  return out;
}

}  // namespace

// The times of a topic's rows, seconds after `origin` (ns).
std::vector<double> MessageLog::seconds_of(const Topic& t, const std::vector<std::size_t>& rows, std::int64_t origin) {
  std::vector<double> seconds(rows.size());
  for (std::size_t i = 0; i < rows.size(); ++i) seconds[i] = static_cast<double>(t.time_ns[rows[i]] - origin) * 1e-9;
  return seconds;
}

log::Log MessageLog::build(const std::optional<Mapping>& mapping) {
  log::Log out;
  out.metadata.source_file = std::filesystem::path(path_).filename().string();
  out.metadata.extra["time"] = options_.time == TimeSource::record ? "record" : "header";
  for (const auto& t : topics_) {
    out.metadata.extra["topic " + t->name] = t->type + ", " + std::to_string(t->time_ns.size()) + " messages";
  }
  const auto find_topic = [&](const std::string& name) -> Topic* {
    for (const auto& t : topics_) {
      if (stream_name(t->name) == stream_name(name)) return t.get();
    }
    return nullptr;
  };

  // The topics to read and the common time origin.
  std::vector<Topic*> chosen;
  if (mapping) {
    const std::string label = mapping->name.empty() ? mapping->source : mapping->name;
    for (const auto& sm : mapping->streams) {
      Topic* t = find_topic(sm.time_variable);
      if (t == nullptr) throw InputError(path_, "mapping " + label + ": no topic " + sm.time_variable + " in the file");
      if (sm.time_unit != "s") {
        throw InputError(path_,
                         "mapping " + label + ": stream " + sm.name + ": a topic's time is in s, not " + sm.time_unit);
      }
      chosen.push_back(t);
    }
  } else {
    for (const auto& t : topics_) chosen.push_back(t.get());
  }
  std::int64_t origin = std::numeric_limits<std::int64_t>::max();
  for (Topic* t : chosen) {
    if (!t->time_ns.empty()) origin = std::min(origin, *std::min_element(t->time_ns.begin(), t->time_ns.end()));
  }
  if (origin_ns_) origin = *origin_ns_;
  if (origin == std::numeric_limits<std::int64_t>::max() || (mapping && mapping->time_origin != "first_sample")) {
    origin = 0;
  }
  if (origin != 0) out.metadata.extra["time_origin"] = seconds_text(origin);

  try {
    if (!mapping) {
      for (Topic* t : chosen) {
        const std::vector<std::size_t> rows = t->rows();
        const bool in_file_order =
            rows.size() == t->time_ns.size() && std::is_sorted(t->time_ns.begin(), t->time_ns.end());
        log::Stream stream(stream_name(t->name), seconds_of(*t, rows, origin));
        for (std::size_t c = 0; c < t->columns.size(); ++c) {
          // A standard message's fields in their REP 103 units (NavSatFix degrees to rad), others "1".
          const bool seconds = t->channel_names[c] == "header.stamp";
          const StandardUnit unit = seconds
                                        ? StandardUnit{"s", 1.0}
                                        : standard_unit(t->type, t->channel_names[c]).value_or(StandardUnit{"1", 1.0});
          // Rows 0, 1, 2, ... (in time order, no repeated time: the common case): moved, not copied.
          // Otherwise each value goes with its own message's time.
          std::vector<double> values = in_file_order ? std::move(t->columns[c]) : picked(t->columns[c], rows);
          if (unit.factor != 1.0) {
            for (double& v : values) v *= unit.factor;
          }
          stream.add_channel(t->channel_names[c], unit.unit, std::move(values));
        }
        out.add_stream(std::move(stream));
      }
      return out;
    }
    const std::string label = mapping->name.empty() ? mapping->source : mapping->name;
    out.metadata.rover_id = mapping->rover_id;
    out.metadata.description = mapping->description;
    out.metadata.extra["mapping"] = mapping->name;
    for (std::size_t k = 0; k < mapping->streams.size(); ++k) {
      out.add_stream(mapped_stream(mapping->streams[k], *chosen[k], label, origin));
    }
  } catch (const DataError& e) {
    throw InputError(path_, e.what());
  }
  return out;
}

// One stream of a mapping, from its topic `t`: the channels it names, in SI
// units, at the messages that carry at least one of them.
log::Stream MessageLog::mapped_stream(const StreamMapping& sm, const Topic& t, const std::string& label,
                                      std::int64_t origin) const {
  const std::vector<std::size_t> rows = t.rows();
  struct Mapped {
    const ChannelMapping* mapping;
    std::string unit;
    std::vector<double> values;
  };
  std::vector<Mapped> mapped;
  for (const auto& cm : sm.channels) {
    const std::string where = "mapping " + label + ": channel " + sm.name + "/" + cm.name + ": ";
    if (cm.component) throw InputError(path_, where + "'component' is for HDF5 variables, not topics");
    // The variable is a topic and a field: the longest topic that starts it.
    const std::string variable = stream_name(cm.variable);
    const Topic* source = nullptr;
    for (const auto& candidate : topics_) {
      const std::string topic = stream_name(candidate->name);
      if (variable.size() > topic.size() + 1 && variable.compare(0, topic.size(), topic) == 0 &&
          variable[topic.size()] == '/' && (source == nullptr || topic.size() > stream_name(source->name).size())) {
        source = candidate.get();
      }
    }
    if (source == nullptr) throw InputError(path_, where + "no topic in the file starts " + cm.variable);
    const std::string field = variable.substr(stream_name(source->name).size() + 1);
    const auto it = source->index.find(field);
    if (it == source->index.end()) {
      throw InputError(path_,
                       where + "topic " + source->name + " (" + source->type + ") has no numeric field " + field);
    }
    // Another topic's field joins the stream when its messages come at the same times.
    const std::vector<std::size_t> source_rows = source == &t ? rows : source->rows();
    bool same_times = source_rows.size() == rows.size();
    for (std::size_t i = 0; same_times && i < rows.size(); ++i) {
      same_times = source->time_ns[source_rows[i]] == t.time_ns[rows[i]];
    }
    if (!same_times) {
      throw InputError(
          path_, where + "topic " + source->name + " is not stamped at the times of the stream's topic " + t.name);
    }
    std::vector<double> values = picked(source->columns[it->second], source_rows);
    const log::UnitConversion si = log::unit_to_si(cm.unit);
    for (double& v : values) v = (v * si.factor + si.offset) * cm.scale + 0.0;  // + 0.0: no -0 from flips
    mapped.push_back({&cm, si.si_unit, std::move(values)});
  }
  // A message without any of the stream's fields (a /tf message that
  // carries other frames) gives no sample.
  std::vector<double> time = seconds_of(t, rows, origin);
  std::vector<std::size_t> keep;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const bool any = mapped.empty() || std::any_of(mapped.begin(), mapped.end(),
                                                   [&](const Mapped& m) { return !std::isnan(m.values[i]); });
    if (any) keep.push_back(i);
  }
  if (keep.size() < rows.size()) {
    time = picked(time, keep);
    for (Mapped& m : mapped) m.values = picked(m.values, keep);
  }
  log::Stream stream(sm.name, std::move(time));
  for (Mapped& m : mapped) {
    stream.add_channel(m.mapping->name, m.unit, std::move(m.values), m.mapping->description);
  }
  return stream;
}

}  // namespace roverlab::io::ros
