#pragma once
// Loading a log named on the command line, with an optional mapping NAME or
// FILE (resolved against the resource folders).

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "importers/log_file.h"

namespace roverlab::app {

io::LoadedLog load_input(const std::string& file, const std::optional<std::string>& mapping);

// A part of a ROS bag or MCAP file (`info` and `convert`'s --topics and
// --time START:END, seconds after the file's first message); a UsageError
// for other formats or a malformed range.
struct RosPart {
  std::vector<std::string> topics;
  std::optional<std::string> time;
};
io::LoadedLog load_input(const std::string& file, const std::optional<std::string>& mapping, const RosPart& part);

// How load_input reads ROS bags and MCAP files: set once from the command
// line's --ros-time and --ros-max-array (app/command_line.cpp).
struct RosInputOptions {
  std::string time = "record";  // "record" or "header"
  std::size_t max_array = 64;
};
RosInputOptions& ros_input_options();

}  // namespace roverlab::app
