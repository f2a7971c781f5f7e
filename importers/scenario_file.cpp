#include "importers/scenario_file.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <iterator>

#include <nlohmann/json.hpp>

#include "core/common/error.h"

#include "importers/json_resource.h"
#include "importers/named_file.h"

namespace roverlab::io {

namespace {

// A name from a file as a message shows it: at most 40 characters, control characters as '?'.
std::string shown(const std::string& name) {
  std::string out;
  for (const char c : name.substr(0, 40)) out += std::isprint(static_cast<unsigned char>(c)) != 0 ? c : '?';
  return name.size() > 40 ? out + "..." : out;
}

const char* const kFields[] = {"format",
                               "version",
                               "name",
                               "description",
                               "kind",
                               "rover",
                               "path",
                               "soil",
                               "traction",
                               "duration_s",
                               "start_x_m",
                               "desired_speed_mps",
                               "slope_deg",
                               "bump_height_m",
                               "bump_x_m",
                               "bump_length_m",
                               "rolling_amplitude_m",
                               "effects"};

// A field the reader does not know is a misspelling, never ignored.
void require_known_scenario_fields(const JsonNode& j) {
  if (!j.value().is_object()) return;
  for (const auto& item : j.value().items()) {
    if (std::find(std::begin(kFields), std::end(kFields), item.key()) != std::end(kFields)) continue;
    std::string known;
    for (const char* f : kFields) known += (known.empty() ? "" : ", ") + std::string(f);
    j.fail(shown(item.key()), "unknown field (known: " + known + ")");
  }
}

ScenarioFile read_scenario(const JsonResource& file) {
  const JsonNode j = file.root();
  require_format(j, "roverlab-scenario", "scenario");
  require_known_scenario_fields(j);
  ScenarioFile s;
  s.file = file.file();
  s.document = j.value().dump();
  s.name = optional_string(j, "name", "");
  if (!s.name.empty() && !is_plain_name(s.name)) {
    j.fail("name", "'" + shown(s.name) + "' is not a plain name (letters, digits, '_', '-', '.'; at most 128)");
  }
  s.description = optional_string(j, "description", "");
  s.kind = required_string(j, "kind");
  s.rover = required_string(j, "rover");
  s.path = required_string(j, "path");
  s.soil = required_string(j, "soil");
  s.traction = optional_string(j, "traction", "polynomial");
  if (s.traction != "polynomial" && s.traction != "wong-reece") {
    j.fail("traction", "'" + s.traction.substr(0, 40) + "': expected polynomial or wong-reece");
  }
  s.duration = required_number(j, "duration_s");
  s.start_x = optional_number(j, "start_x_m", 0.0);
  s.desired_speed = optional_number(j, "desired_speed_mps", 0.02);
  s.slope_deg = optional_number(j, "slope_deg", 0.0);
  s.bump_height = optional_number(j, "bump_height_m", 0.05);
  s.bump_x = optional_number(j, "bump_x_m", 1.0);
  s.bump_length = optional_number(j, "bump_length_m", 0.3);
  s.rolling_amplitude = optional_number(j, "rolling_amplitude_m", 0.12);
  // Steeper than 0.5 m over the 4 m wavelength is a wall (crests beyond 38 deg).
  if (!(s.rolling_amplitude >= 0 && s.rolling_amplitude <= 0.5)) j.fail("rolling_amplitude_m", "must be 0..0.5 (m)");
  if (j.has("effects")) {
    const JsonNode effects = required_object(j, "effects");
    for (const auto& item : effects.value().items()) s.effects[item.key()] = as_number(effects.child(item.key()));
  }
  if (s.kind != "rocker-bogie") j.fail("kind", "scenario kind '" + s.kind + "' is not rocker-bogie");
  // A run shorter than 0.1 s holds a handful of samples, no log.
  if (!(s.duration >= 0.1)) j.fail("duration_s", "must be at least 0.1 (s)");
  if (!(s.duration <= 100000)) j.fail("duration_s", "must be at most 100000 (s)");
  if (!(s.desired_speed > 0)) j.fail("desired_speed_mps", "must be positive");
  // A planetary rover drives at centimetres per second; 2 m/s is far beyond any.
  if (!(s.desired_speed <= 2)) j.fail("desired_speed_mps", "must be at most 2 (m/s)");
  // Far from the origin the path's doubles lose the millimetres the contact needs.
  if (!(std::abs(s.start_x) <= 1000)) j.fail("start_x_m", "must be within +-1000 (m)");
  if (!(std::abs(s.bump_x) <= 1000)) j.fail("bump_x_m", "must be within +-1000 (m)");
  return s;
}

}  // namespace

bool is_plain_name(const std::string& name) {
  return !name.empty() && name.size() <= 128 && name.front() != '.' &&
         name.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_-.") ==
             std::string::npos;
}

ScenarioFile load_scenario(const std::string& path) { return read_scenario(read_json_resource(path, "scenario")); }

ScenarioFile parse_scenario(const std::string& source, const std::string& text) {
  if (json_nesting(text) > kMaxJsonNesting) {
    throw InputError(source, "the recorded scenario nests deeper than " + std::to_string(kMaxJsonNesting) + " levels");
  }
  nlohmann::json doc;
  try {
    doc = nlohmann::json::parse(text);
  } catch (const nlohmann::json::exception& e) {
    throw InputError(source, std::string("the recorded scenario is not valid JSON: ") + e.what());
  }
  return read_scenario(JsonResource(source, std::move(doc)));
}

ScenarioFile find_scenario_named(const std::string& name, const std::vector<std::filesystem::path>& folders,
                                 const std::string& source) {
  if (!is_plain_name(name) || std::filesystem::path(name).extension() == ".json") {
    throw InputError(source, "scenario '" + shown(name) +
                                 "' is not a scenario name (a name from resources/scenarios, never a path)");
  }
  for (const auto& folder : folders) {
    const std::filesystem::path candidate = folder / (name + ".json");
    std::error_code ec;
    if (std::filesystem::is_regular_file(candidate, ec)) return load_scenario(candidate.string());
  }
  return load_scenario(find_named_file(name, folders, "scenario"));  // the usual "no scenario of that name"
}

ScenarioFile find_scenario(const std::string& name_or_file, const std::vector<std::filesystem::path>& folders) {
  return load_scenario(find_named_file(name_or_file, folders, "scenario"));
}

}  // namespace roverlab::io
