// `roverlab info`, `roverlab convert` and `roverlab mappings`.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <nlohmann/json.hpp>

#include <CLI/CLI.hpp>

#include "app/command.h"
#include "app/command_support.h"
#include "app/commands.h"
#include "app/log_input.h"
#include "app/resources.h"
#include "core/common/error.h"
#include "importers/csv_log.h"
#include "importers/hdf5_log.h"
#include "importers/log_file.h"

namespace roverlab::app {

struct InfoOptions {
  std::string file;
  std::optional<std::string> mapping;
  bool json = false;
  RosPart part;  // --topics, --time
};

struct ConvertOptions {
  std::string input;
  std::string output;
  std::optional<std::string> mapping;
  std::optional<std::string> stream;  // the one stream a CSV output takes
  RosPart part;                       // --topics, --time
};

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

struct ChannelStats {
  double min = NAN, max = NAN;
  std::size_t missing = 0;
};

ChannelStats stats(const std::vector<double>& values) {
  ChannelStats s;
  for (double v : values) {
    if (std::isnan(v)) {
      ++s.missing;
      continue;
    }
    if (std::isnan(s.min) || v < s.min) s.min = v;
    if (std::isnan(s.max) || v > s.max) s.max = v;
  }
  return s;
}

std::string fmt(const char* format, double v) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, format, v);
  return buffer;
}

}  // namespace

int run_info(const InfoOptions& options) {
  const io::LoadedLog loaded = load_input(options.file, options.mapping, options.part);
  const log::Log& lg = loaded.log;
  const auto& meta = lg.metadata;
  if (options.json) {
    json out;
    out["file"] = options.file;
    out["format"] = loaded.format;
    out["metadata"] = {{"rover_id", meta.rover_id},
                       {"source_file", meta.source_file},
                       {"description", meta.description},
                       {"extra", meta.extra}};
    out["streams"] = json::array();
    for (const auto& s : lg.streams()) {
      json js = {{"name", s.name()},
                 {"samples", s.size()},
                 {"rate_hz", s.mean_rate_hz()},
                 {"duration_s", s.duration()},
                 {"start_s", s.empty() ? json(nullptr) : json(s.start_time())},
                 {"end_s", s.empty() ? json(nullptr) : json(s.end_time())},
                 {"channels", json::array()}};
      for (const auto& c : s.channels()) {
        const ChannelStats st = stats(c.values);
        js["channels"].push_back({{"name", c.name},
                                  {"unit", c.unit},
                                  {"description", c.description},
                                  {"min", std::isnan(st.min) ? json(nullptr) : json(st.min)},
                                  {"max", std::isnan(st.max) ? json(nullptr) : json(st.max)},
                                  {"missing", st.missing}});
      }
      out["streams"].push_back(js);
    }
    std::cout << out.dump(2) << "\n";
    return kSuccess;
  }

  std::cout << "file     " << options.file << "\n"
            << "format   " << loaded.format;
  if (meta.extra.count("mapping") != 0) std::cout << " (mapping " << meta.extra.at("mapping") << ")";
  std::cout << "\n";
  // Text from the file never reaches the terminal as control characters.
  if (!meta.rover_id.empty()) std::cout << "rover    " << printable(meta.rover_id) << "\n";
  if (!meta.source_file.empty()) std::cout << "source   " << printable(meta.source_file, 1000) << "\n";
  if (!meta.description.empty()) std::cout << "about    " << printable(meta.description, 1000) << "\n";
  for (const auto& [key, value] : meta.extra) {
    if (key == "scenario_json") {
      std::cout << key << " = (the scenario the log was simulated from, " << value.size() << " characters)\n";
    } else if (key != "mapping") {
      std::cout << printable(key) << " = " << printable(value, 1000) << "\n";
    }
  }
  std::cout << "streams  " << lg.streams().size() << "\n";
  for (const auto& s : lg.streams()) {
    std::cout << "\nstream " << printable(s.name(), 1000) << ": " << s.size() << " samples";
    if (s.size() >= 2) {
      // A time base of 1e300 s prints as such, not as 300 digits (F42).
      auto shown = [](const char* format, double v) { return std::abs(v) < 1e9 ? fmt(format, v) : fmt("%.6g", v); };
      std::cout << ", " << shown("%.1f", s.mean_rate_hz()) << " Hz, " << shown("%.2f", s.duration())
                << " s (t = " << shown("%.3f", s.start_time()) << " .. " << shown("%.3f", s.end_time()) << " s)";
    }
    std::cout << "\n";
    // Names from the file (topics, JSON keys, joint names) with control characters as \xHH.
    std::size_t width = 4;
    for (const auto& c : s.channels()) width = std::max(width, printable(c.name, 1000).size());
    for (const auto& c : s.channels()) {
      const ChannelStats st = stats(c.values);
      const std::string name = printable(c.name, 1000);
      std::string line = "  " + name + std::string(width - name.size() + 2, ' ');
      std::string unit = "[" + printable(c.unit) + "]";
      unit.resize(std::max<std::size_t>(unit.size(), 10), ' ');
      line += std::isnan(st.min) ? unit + "no finite values"
                                 : unit + fmt("%12.5g", st.min) + " .. " + fmt("%-12.5g", st.max);
      if (st.missing > 0) line += " (" + std::to_string(st.missing) + " missing)";
      if (!c.description.empty()) line += "  " + printable(c.description, 1000);
      std::cout << line << "\n";
    }
  }
  return kSuccess;
}

int run_convert(const ConvertOptions& options) {
  const std::string ext = fs::path(options.output).extension().string();
  const bool to_csv = ext == ".csv";
  const std::string name = fs::path(options.output).filename().string();
  if (name == ".h5" || name == ".hdf5" || name == ".csv") {
    std::cerr << "roverlab convert: " << options.output << ": the output has no name before its extension\n";
    return kUsageError;
  }
  if (!to_csv && ext != ".h5" && ext != ".hdf5") {
    std::cerr << "roverlab convert: " << options.output
              << ": output must end in .h5 or .hdf5 (RoverLab HDF5 log) or .csv (one stream)\n";
    return kUsageError;
  }
  refuse_overwriting_input(options.input, options.output, "OUT");
  const io::LoadedLog loaded = load_input(options.input, options.mapping, options.part);
  if (to_csv) {
    const log::Log& lg = loaded.log;
    if (options.stream) {
      const log::Stream* s = lg.find_stream(*options.stream);
      if (s == nullptr) throw InputError(options.input, "has no stream '" + *options.stream + "'");
      io::write_csv_stream(*s, options.output);
      std::cout << "wrote " << options.output << ": stream " << s->name() << ", " << s->size() << " samples\n";
      return kSuccess;
    }
    if (lg.streams().size() != 1) {
      throw InputError(options.input,
                       "has " + std::to_string(lg.streams().size()) +
                           " streams; CSV output holds exactly one (choose it with --stream, or use .h5)");
    }
    io::write_csv_stream(lg.streams().front(), options.output);
  } else {
    io::write_hdf5_log(loaded.log, options.output);
  }
  std::cout << "wrote " << options.output << ": " << loaded.log.streams().size() << " streams, "
            << loaded.log.total_samples() << " values\n";
  return kSuccess;
}

int run_list_mappings() {
  for (const auto& folder : resource_subfolders("mappings")) {
    for (const auto& name : io::list_mappings({folder})) {
      std::cout << name << "  " << (folder / (name + ".json")).string() << "\n";
    }
  }
  return kSuccess;
}

namespace {
void add_ros_part_options(CLI::App& cmd, RosPart& part) {
  cmd.add_option("--topics", part.topics, "ROS bag or MCAP input: only these topics (comma-separated)")->delimiter(',');
  cmd.add_option("--time", part.time,
                 "ROS bag or MCAP input: only START:END, seconds after the file's first message (either may be "
                 "empty); MCAP files with a summary read only the chunks that hold it");
}
}  // namespace

Commands make_log_commands() {
  Commands commands;
  commands.push_back(make_command<InfoOptions>(
      "info", "List a log's streams and channels with units, sample counts, rates and durations",
      [](CLI::App& cmd, InfoOptions& o) {
        cmd.add_option("FILE", o.file, "Log file: RoverLab HDF5, MATLAB v7.3 (.mat), CSV, ROS 1 bag or MCAP")
            ->required();
        cmd.add_option("--mapping,-m", o.mapping,
                       "Mapping NAME (resources/mappings/NAME.json) or FILE for .mat/HDF5, bag or MCAP input");
        cmd.add_flag("--json", o.json, "Print JSON instead of text");
        add_ros_part_options(cmd, o.part);
      },
      run_info));
  commands.push_back(make_command<ConvertOptions>(
      "convert", "Convert a log to a RoverLab HDF5 log (or a one-stream CSV)",
      [](CLI::App& cmd, ConvertOptions& o) {
        cmd.add_option("IN", o.input, "Input log: HDF5, MATLAB v7.3 (.mat), CSV, ROS 1 bag or MCAP")->required();
        cmd.add_option("OUT", o.output, "Output file: .h5 / .hdf5, or .csv")->required();
        cmd.add_option("--mapping,-m", o.mapping,
                       "Mapping NAME (resources/mappings/NAME.json) or FILE for .mat/HDF5, bag or MCAP input");
        cmd.add_option("--stream,-s", o.stream, "For .csv output: the stream to write");
        add_ros_part_options(cmd, o.part);
      },
      run_convert));
  struct NoOptions {};
  commands.push_back(make_command<NoOptions>(
      "mappings", "List the importer mappings RoverLab knows", [](CLI::App&, NoOptions&) {},
      [](const NoOptions&) { return run_list_mappings(); }));
  return commands;
}

}  // namespace roverlab::app
