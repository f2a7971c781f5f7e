#pragma once
// A campaign file: which logs and which simulated runs a campaign processes
// (docs/campaigns.md). JSON with "format": "roverlab-campaign", "version": 1;
// read through json_resource.h, so every error names the file and the field.
// Relative paths inside it are relative to the campaign file's folder.

#include <map>
#include <optional>
#include <string>
#include <vector>

namespace roverlab::io {

// One log, or every log of a folder (not its subfolders: .h5 .hdf5 .mat .csv).
struct CampaignLogs {
  std::string file;                    // absolute; empty for a folder entry
  std::string folder;                  // absolute; empty for a file entry
  std::optional<std::string> mapping;  // NAME or FILE, as written
  std::string where;                   // "logs[2]", for messages
};

// Simulated runs: every seed with every effect set.
struct CampaignSimulations {
  std::string command;   // "scenario" (roverlab scenario NAME) or "simulate" (roverlab simulate NAME)
  std::string scenario;  // skid-steer-slip, fl-bogie-rotation, ...; or a simulate scenario NAME or FILE
  std::vector<unsigned> seeds;
  std::vector<std::map<std::string, double>> effects;  // at least one set (the empty set: no effect)
  std::optional<double> rate;                          // Hz, flying-rover scenarios
  std::optional<double> turn_radius;                   // m, flying-rover scenarios (--turn-radius)
  std::optional<double> slip_angle_deg;                // deg, flying-rover scenarios (--slip-angle)
  std::optional<double> slip_angle_from;               // s, flying-rover scenarios (--slip-angle-from)
  std::optional<double> duration;                      // s, simulate
  std::string where;                                   // "simulations[0]"
};

struct CampaignFile {
  std::string file;
  std::string name;
  std::vector<CampaignLogs> logs;
  std::vector<CampaignSimulations> simulations;
};

// The scenarios `roverlab scenario NAME` writes: skid-steer-slip and core's
// flying-rover scenarios (simulation::flying_rover_scenarios(), the list the
// command registers), so a new scenario needs no edit here.
const std::vector<std::string>& campaign_scenario_names();

// The steering manoeuvre's fields of a flying-rover entry: the campaign
// field, the `roverlab scenario` option it becomes, and where it is read to.
struct FlyingRoverField {
  const char* name;    // "turn_radius"
  const char* option;  // "--turn-radius"
  std::optional<double> CampaignSimulations::*value;
};
inline constexpr FlyingRoverField kFlyingRoverFields[] = {
    {"turn_radius", "--turn-radius", &CampaignSimulations::turn_radius},
    {"slip_angle_deg", "--slip-angle", &CampaignSimulations::slip_angle_deg},
    {"slip_angle_from", "--slip-angle-from", &CampaignSimulations::slip_angle_from}};

// Reads and checks a campaign file: format and version, field types, numeric
// ranges (seeds 0..2^31-1, at most 10000 runs), scenario names, and which
// options a scenario takes. Effect names and values, and the steering
// manoeuvre's values (turn_radius, slip_angle_deg, slip_angle_from: their
// bounds depend on the scenario's duration), are checked by the caller, which
// knows the simulators. Throws InputError naming the file and the field.
CampaignFile read_campaign_file(const std::string& path);

}  // namespace roverlab::io
