#include "importers/mapping.h"

#include <cmath>

#include <set>

#include "core/log/stream.h"
#include "core/log/units.h"
#include "importers/json_resource.h"
#include "importers/named_file.h"

namespace roverlab::io {

namespace fs = std::filesystem;
namespace {

std::string unit_field(const JsonNode& node, const std::string& field, const std::string& fallback) {
  std::string unit = optional_string(node, field, fallback);
  if (!log::is_known_unit(unit)) node.fail(field, "unknown unit '" + unit + "'");
  return unit;
}

ChannelMapping parse_channel(const JsonNode& jc, std::set<std::string>& channel_names) {
  ChannelMapping c;
  c.name = required_string(jc, "name");
  if (!log::is_valid_channel_name(c.name)) jc.fail("name", "invalid channel name '" + c.name + "'");
  if (!channel_names.insert(c.name).second) jc.fail("name", "channel '" + c.name + "' appears twice");
  c.variable = required_string(jc, "variable");
  c.unit = unit_field(jc, "unit", "1");
  c.description = optional_string(jc, "description", "");
  if (jc.has("component")) {
    if (!jc.value().at("component").is_number_unsigned()) jc.fail("component", "expected a non-negative integer");
    c.component = jc.value().at("component").get<std::size_t>();
  }
  c.scale = optional_number(jc, "scale", 1.0);
  // A factor of 1e308 turns every value into inf: no unit needs more than 1e6.
  if (!(std::abs(c.scale) <= 1e6 && std::abs(c.scale) >= 1e-6)) jc.fail("scale", "must be within 1e-6 to 1e6 in size");
  return c;
}

StreamMapping parse_stream(const JsonNode& js, std::set<std::string>& stream_names) {
  StreamMapping s;
  s.name = required_string(js, "name");
  if (!log::is_valid_stream_name(s.name)) js.fail("name", "invalid stream name '" + s.name + "'");
  if (!stream_names.insert(s.name).second) js.fail("name", "stream '" + s.name + "' appears twice");
  const JsonNode time = required_object(js, "time");
  s.time_variable = required_string(time, "variable");
  s.time_unit = unit_field(time, "unit", "s");
  if (log::unit_to_si(s.time_unit).si_unit != "s") {
    time.fail("unit", "unit '" + s.time_unit + "' is not a unit of time");
  }
  std::set<std::string> channel_names;
  for (const auto& jc : required_array(js, "channels")) s.channels.push_back(parse_channel(jc, channel_names));
  return s;
}

}  // namespace

Mapping load_mapping(const std::string& path) {
  const JsonResource file = read_json_resource(path, "mapping file");
  const JsonNode root = file.root();
  require_format(root, "roverlab-mapping", "mapping");
  if (optional_number(root, "version", 0) != 1) root.fail("version", "unsupported mapping version (expected 1)");
  Mapping m;
  m.name = required_string(root, "name");
  m.description = optional_string(root, "description", "");
  m.rover_id = optional_string(root, "rover_id", "");
  m.time_origin = optional_string(root, "time_origin", "first_sample");
  if (m.time_origin != "first_sample" && m.time_origin != "none") {
    root.fail("time_origin", "expected \"first_sample\" or \"none\"");
  }
  const std::vector<JsonNode> streams = required_array(root, "streams");
  if (streams.empty()) root.fail("streams", "expected a non-empty array");
  std::set<std::string> stream_names;
  for (const auto& js : streams) m.streams.push_back(parse_stream(js, stream_names));
  m.source = path;
  return m;
}

std::string find_mapping(const std::string& name_or_file, const std::vector<fs::path>& folders) {
  return find_named_file(name_or_file, folders, "mapping");
}

std::vector<std::string> list_mappings(const std::vector<fs::path>& folders) { return list_named_files(folders); }

}  // namespace roverlab::io
