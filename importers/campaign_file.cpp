#include "importers/campaign_file.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <initializer_list>

#include "core/common/error.h"
#include "core/simulation/flying_rover.h"
#include "importers/json_resource.h"

namespace roverlab::io {

namespace {

namespace fs = std::filesystem;

constexpr double kMaxSeed = 2147483647.0;
// Snakemake plans 10,000 runs in about 40 s and 650 MB before the first one
// starts; 100,000 took minutes with no output (issue 34, N9).
constexpr std::size_t kMaxRuns = 10000;

std::string absolute_from(const fs::path& base, const std::string& path) {
  const fs::path p(path);
  return (p.is_absolute() ? p : base / p).lexically_normal().string();
}

// A FILE (relative to the campaign file) rather than a resource NAME.
bool names_a_file(const std::string& s) {
  return s.find('/') != std::string::npos || (s.size() > 5 && s.compare(s.size() - 5, 5, ".json") == 0);
}

// A field the reader does not know is a misspelling ("seed" for "seeds"), never ignored.
void require_known_fields(const JsonNode& node, std::initializer_list<const char*> known) {
  for (const auto& item : node.value().items()) {
    if (std::any_of(known.begin(), known.end(), [&](const char* k) { return item.key() == k; })) continue;
    std::string list;
    for (const char* k : known) list += (list.empty() ? "" : ", ") + std::string(k);
    std::string key;  // as a message shows it: no control characters, at most 40 of them
    for (const char c : item.key().substr(0, 40)) key += std::isprint(static_cast<unsigned char>(c)) != 0 ? c : '?';
    node.fail(key, "unknown field (" + list + ")");
  }
}

unsigned seed_of(const JsonNode& node) {
  const double v = as_number(node);
  if (!(v >= 0 && v <= kMaxSeed) || std::floor(v) != v) node.fail("a seed is a whole number in 0..2147483647");
  return static_cast<unsigned>(v);
}

std::vector<unsigned> read_seeds(const JsonNode& entry) {
  if (!entry.has("seeds")) return {1};
  const JsonNode seeds = entry.child("seeds");
  std::vector<unsigned> out;
  if (seeds.value().is_array()) {
    for (const auto& s : required_array(entry, "seeds")) out.push_back(seed_of(s));
    if (out.empty()) seeds.fail("lists no seed");
  } else if (seeds.value().is_object()) {
    require_known_fields(seeds, {"first", "count"});
    const double first = required_number_in(seeds, "first", 0, kMaxSeed);
    const double count = required_number_in(seeds, "count", 1, static_cast<double>(kMaxRuns));
    if (std::floor(first) != first) seeds.fail("first", "must be a whole number");
    if (std::floor(count) != count) seeds.fail("count", "must be a whole number");
    if (first + count - 1 > kMaxSeed) seeds.fail("count", "the last seed would pass 2147483647");
    for (double s = first; s < first + count; s += 1) out.push_back(static_cast<unsigned>(s));
  } else {
    seeds.fail("expected an array of seeds or {\"first\": N, \"count\": N}");
  }
  return out;
}

std::vector<std::map<std::string, double>> read_effects(const JsonNode& entry) {
  if (!entry.has("effects")) return {{}};
  std::vector<std::map<std::string, double>> out;
  for (const auto& set : required_array(entry, "effects")) {
    if (!set.value().is_object()) set.fail("expected an object of effect NAME: VALUE ({} for none)");
    std::map<std::string, double> effects;
    for (const auto& item : set.value().items()) effects[item.key()] = as_number(set.child(item.key()));
    out.push_back(effects);
  }
  if (out.empty()) entry.fail("effects", "lists no effect set (use [{}] for runs without an effect)");
  return out;
}

CampaignLogs read_logs(const JsonNode& entry, const fs::path& base) {
  if (!entry.value().is_object()) entry.fail("expected an object with \"file\" or \"folder\"");
  require_known_fields(entry, {"file", "folder", "mapping"});
  CampaignLogs logs;
  logs.where = entry.where();
  const bool file = entry.has("file"), folder = entry.has("folder");
  if (file == folder) entry.fail("needs one of \"file\" or \"folder\"");
  std::error_code ec;
  if (file) {
    logs.file = absolute_from(base, required_string(entry, "file"));
    if (fs::is_directory(logs.file, ec)) entry.fail("file", logs.file + " is a folder: give it as \"folder\"");
    if (fs::exists(logs.file, ec) && !fs::is_regular_file(logs.file, ec)) {
      entry.fail("file", logs.file + " is not a regular file (a device, pipe or socket)");
    }
    if (!fs::is_regular_file(logs.file, ec)) entry.fail("file", "no such file: " + logs.file);
  } else {
    logs.folder = absolute_from(base, required_string(entry, "folder"));
    if (fs::exists(logs.folder, ec) && !fs::is_directory(logs.folder, ec)) {
      entry.fail("folder", logs.folder + " is not a folder: give a file as \"file\"");
    }
    if (!fs::is_directory(logs.folder, ec)) entry.fail("folder", "no such folder: " + logs.folder);
  }
  if (entry.has("mapping")) {
    std::string mapping = required_string(entry, "mapping");
    // A mapping FILE is relative to the campaign file; a NAME stays a name.
    if (names_a_file(mapping)) mapping = absolute_from(base, mapping);
    logs.mapping = mapping;
  }
  return logs;
}

bool is_flying_rover_scenario(const std::string& name) {
  const std::vector<std::string> flying = simulation::flying_rover_scenarios();
  return std::find(flying.begin(), flying.end(), name) != flying.end();
}

// rate, turn_radius, slip_angle_deg, slip_angle_from: a flying-rover scenario's, refused elsewhere.
void read_flying_rover_options(const JsonNode& entry, CampaignSimulations& s) {
  const bool flying = s.command == "scenario" && is_flying_rover_scenario(s.scenario);
  const auto refuse = [&](const char* field) {
    if (s.command == "scenario") entry.fail(field, s.scenario + " has no " + field + " option");
    entry.fail(field, std::string("only flying-rover scenarios take a ") + field);
  };
  if (entry.has("rate")) {
    if (!flying) refuse("rate");
    s.rate = required_number_in(entry, "rate", 10, 10000);
  }
  for (const auto& f : kFlyingRoverFields) {
    if (!entry.has(f.name)) continue;
    if (!flying) refuse(f.name);
    s.*f.value = required_number(entry, f.name);
  }
  // A start without a slip angle has no effect (and would name the run as if it had).
  if (entry.has("slip_angle_from") && !entry.has("slip_angle_deg")) {
    entry.fail("slip_angle_from", "needs slip_angle_deg: without a slip angle it has no effect");
  }
}

CampaignSimulations read_simulations(const JsonNode& entry, const fs::path& base) {
  if (!entry.value().is_object()) entry.fail("expected an object with \"scenario\" or \"simulate\"");
  require_known_fields(entry, {"scenario", "simulate", "seeds", "effects", "rate", "turn_radius", "slip_angle_deg",
                               "slip_angle_from", "duration"});
  CampaignSimulations s;
  s.where = entry.where();
  const bool scenario = entry.has("scenario"), simulate = entry.has("simulate");
  if (scenario == simulate)
    entry.fail("needs one of \"scenario\" (roverlab scenario) or \"simulate\" (roverlab simulate)");
  if (scenario) {
    s.command = "scenario";
    s.scenario = required_string(entry, "scenario");
    const auto& names = campaign_scenario_names();
    if (std::find(names.begin(), names.end(), s.scenario) == names.end()) {
      std::string list;
      for (const auto& n : names) list += (list.empty() ? "" : ", ") + n;
      entry.fail("scenario", "unknown scenario '" + s.scenario + "' (" + list + ")");
    }
    if (entry.has("duration")) entry.fail("duration", "only \"simulate\" runs take a duration");
  } else {
    s.command = "simulate";
    s.scenario = required_string(entry, "simulate");
    if (names_a_file(s.scenario)) s.scenario = absolute_from(base, s.scenario);
    if (entry.has("duration")) {
      s.duration = required_number_in(entry, "duration", 0, 100000);
      if (!(*s.duration > 0)) entry.fail("duration", "must be positive");
    }
  }
  read_flying_rover_options(entry, s);
  s.seeds = read_seeds(entry);
  s.effects = read_effects(entry);
  return s;
}

}  // namespace

const std::vector<std::string>& campaign_scenario_names() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> out = {"skid-steer-slip"};
    for (const auto& name : simulation::flying_rover_scenarios()) out.push_back(name);
    return out;
  }();
  return names;
}

CampaignFile read_campaign_file(const std::string& path) {
  const JsonResource file = read_json_resource(path, "campaign");
  const JsonNode j = file.root();
  require_format(j, "roverlab-campaign", "campaign");
  const double version = required_number(j, "version");
  if (version != 1) j.fail("version", "version " + j.value().at("version").dump() + " is not supported (1 is)");
  for (const auto& item : j.value().items()) {
    const std::string& k = item.key();
    if (k != "format" && k != "version" && k != "name" && k != "description" && k != "logs" && k != "simulations") {
      j.fail(k, "unknown field (format, version, name, description, logs, simulations)");
    }
  }
  CampaignFile c;
  c.file = path;
  c.name = optional_string(j, "name", fs::path(path).stem().string());
  (void)optional_string(j, "description", "");
  const fs::path base = fs::absolute(fs::path(path)).parent_path();
  if (j.has("logs")) {
    for (const auto& e : required_array(j, "logs")) c.logs.push_back(read_logs(e, base));
  }
  std::size_t runs = 0;
  if (j.has("simulations")) {
    for (const auto& e : required_array(j, "simulations")) {
      c.simulations.push_back(read_simulations(e, base));
      runs += c.simulations.back().seeds.size() * c.simulations.back().effects.size();
      if (runs > kMaxRuns) e.fail("the campaign would pass 10000 simulated runs");
    }
  }
  if (c.logs.empty() && c.simulations.empty()) j.fail("names no \"logs\" and no \"simulations\"");
  return c;
}

}  // namespace roverlab::io
