#include "importers/mapping.h"

#include <algorithm>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>

#include "core/common/error.h"
#include "core/log/stream.h"
#include "core/log/units.h"
#include "importers/named_file.h"

namespace roverlab::io {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

std::string required_string(const json& object, const char* key, const std::string& where) {
  if (!object.contains(key) || !object.at(key).is_string()) {
    throw DataError(where + ": '" + key + "' must be a string");
  }
  return object.at(key).get<std::string>();
}

std::string optional_string(const json& object, const char* key, const std::string& where,
                            const std::string& fallback) {
  if (!object.contains(key)) return fallback;
  if (!object.at(key).is_string()) throw DataError(where + ": '" + key + "' must be a string");
  return object.at(key).get<std::string>();
}

void check_unit(const std::string& unit, const std::string& where) {
  if (!log::is_known_unit(unit)) {
    throw DataError(where + ": unknown unit '" + unit + "'");
  }
}

Mapping parse(const json& root) {
  Mapping m;
  if (!root.is_object()) throw DataError("top level must be a JSON object");
  if (root.value("format", std::string()) != "roverlab-mapping") {
    throw DataError("not a RoverLab mapping ('format' must be \"roverlab-mapping\")");
  }
  if (root.value("version", 0) != 1) throw DataError("unsupported mapping version (expected 1)");
  m.name = required_string(root, "name", "mapping");
  m.description = optional_string(root, "description", "mapping", "");
  m.rover_id = optional_string(root, "rover_id", "mapping", "");
  m.time_origin = optional_string(root, "time_origin", "mapping", "first_sample");
  if (m.time_origin != "first_sample" && m.time_origin != "none") {
    throw DataError("'time_origin' must be \"first_sample\" or \"none\"");
  }
  if (!root.contains("streams") || !root.at("streams").is_array() || root.at("streams").empty()) {
    throw DataError("'streams' must be a non-empty array");
  }
  std::set<std::string> stream_names;
  for (const auto& js : root.at("streams")) {
    StreamMapping s;
    s.name = required_string(js, "name", "stream");
    const std::string where = "stream '" + s.name + "'";
    if (!log::is_valid_stream_name(s.name)) throw DataError(where + ": invalid stream name");
    if (!stream_names.insert(s.name).second) throw DataError(where + " appears twice");
    if (!js.contains("time") || !js.at("time").is_object()) {
      throw DataError(where + ": 'time' must be an object with 'variable' and 'unit'");
    }
    s.time_variable = required_string(js.at("time"), "variable", where + ", time");
    s.time_unit = optional_string(js.at("time"), "unit", where + ", time", "s");
    check_unit(s.time_unit, where + ", time");
    if (log::unit_to_si(s.time_unit).si_unit != "s") {
      throw DataError(where + ", time: unit '" + s.time_unit + "' is not a unit of time");
    }
    if (!js.contains("channels") || !js.at("channels").is_array()) {
      throw DataError(where + ": 'channels' must be an array");
    }
    std::set<std::string> channel_names;
    for (const auto& jc : js.at("channels")) {
      ChannelMapping c;
      c.name = required_string(jc, "name", where + ", channel");
      const std::string cwhere = where + ", channel '" + c.name + "'";
      if (!log::is_valid_channel_name(c.name)) throw DataError(cwhere + ": invalid channel name");
      if (!channel_names.insert(c.name).second) throw DataError(cwhere + " appears twice");
      c.variable = required_string(jc, "variable", cwhere);
      c.unit = optional_string(jc, "unit", cwhere, "1");
      check_unit(c.unit, cwhere);
      c.description = optional_string(jc, "description", cwhere, "");
      if (jc.contains("component")) {
        if (!jc.at("component").is_number_unsigned()) {
          throw DataError(cwhere + ": 'component' must be a non-negative integer");
        }
        c.component = jc.at("component").get<std::size_t>();
      }
      if (jc.contains("scale")) {
        if (!jc.at("scale").is_number()) throw DataError(cwhere + ": 'scale' must be a number");
        c.scale = jc.at("scale").get<double>();
      }
      s.channels.push_back(std::move(c));
    }
    m.streams.push_back(std::move(s));
  }
  return m;
}

}  // namespace

Mapping load_mapping(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path, "cannot open mapping file");
  json root;
  try {
    root = json::parse(in);
  } catch (const json::parse_error& e) {
    throw InputError(path, std::string("mapping is not valid JSON: ") + e.what());
  }
  try {
    Mapping m = parse(root);
    m.source = path;
    return m;
  } catch (const DataError& e) {
    throw InputError(path, e.what());
  } catch (const json::exception& e) {
    throw InputError(path, std::string("malformed mapping: ") + e.what());
  }
}

std::string find_mapping(const std::string& name_or_file,
                         const std::vector<fs::path>& folders) {
  return find_named_file(name_or_file, folders, "mapping");
}

std::vector<std::string> list_mappings(const std::vector<fs::path>& folders) {
  return list_named_files(folders);
}

}  // namespace roverlab::io
