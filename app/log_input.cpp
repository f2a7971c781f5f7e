#include "app/log_input.h"

#include "app/commands.h"
#include "app/resources.h"
#include "core/common/error.h"
#include "importers/mapping.h"
#include "importers/ros_message_log.h"

namespace roverlab::app {

RosInputOptions& ros_input_options() {
  static RosInputOptions options;
  return options;
}

io::LoadedLog load_input(const std::string& file, const std::optional<std::string>& mapping) {
  return load_input(file, mapping, RosPart{});
}

io::LoadedLog load_input(const std::string& file, const std::optional<std::string>& mapping, const RosPart& part) {
  io::LoadOptions options;
  options.topics = part.topics;
  if (part.time) {
    try {
      io::ros::parse_time_range(*part.time, options.start_s, options.end_s);
    } catch (const DataError& e) {
      throw UsageError(std::string("--time: ") + e.what());
    }
  }
  if (!part.topics.empty() || part.time) {
    const io::LogReader* reader = io::find_log_reader(file);
    if (reader != nullptr && reader->name() != "ROS 1 bag" && reader->name() != "MCAP") {
      throw UsageError("--topics and --time read a part of a ROS bag or MCAP file, not of a " + reader->name());
    }
  }
  options.header_time = ros_input_options().time == "header";
  options.max_array = ros_input_options().max_array;
  if (mapping) {
    options.mapping = io::load_mapping(io::find_mapping(*mapping, resource_subfolders("mappings")));
  }
  io::LoadedLog loaded = io::load_log(file, options);
  // A range outside the file would write an empty log with exit 0.
  if (part.time && loaded.log.total_samples() == 0) {
    throw InputError(file, "no message in --time " + *part.time + " (seconds after the file's first message)");
  }
  return loaded;
}

void apply_effect_options(const std::vector<std::string>& options,
                          const std::function<void(const std::string& name, double value)>& set) {
  for (const auto& e : options) {
    const auto eq = e.find('=');
    if (eq == std::string::npos) throw UsageError("--effect " + e + ": expected NAME=VALUE");
    double value = 0.0;
    try {
      std::size_t used = 0;
      value = std::stod(e.substr(eq + 1), &used);
      if (used != e.size() - eq - 1) throw std::invalid_argument("trailing text");
    } catch (const std::exception&) {
      throw UsageError("--effect " + e + ": the value is not a number");
    }
    try {
      set(e.substr(0, eq), value);
    } catch (const DataError& err) {
      throw UsageError(std::string("--effect: ") + err.what());
    }
  }
}

}  // namespace roverlab::app
