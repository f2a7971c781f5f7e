// The command line built from the registered commands (app/commands.def), and
// the one place where errors become exit codes.
#include <CLI/CLI.hpp>
#include <iostream>
#include <map>
#include <optional>
#include <stdexcept>

#include "app/command.h"
#include "app/command_support.h"
#include "app/commands.h"
#include "app/log_input.h"
#include "core/common/error.h"
#include "core/common/library_messages.h"
#include "core/common/thread_pool.h"
#include "views/offscreen.h"
#include "views/x_display.h"

#ifndef ROVERLAB_VERSION
#define ROVERLAB_VERSION "unknown"
#endif

namespace roverlab::app {

#define ROVERLAB_COMMANDS(name) Commands make_##name##_commands();
#include "app/commands.def"
#undef ROVERLAB_COMMANDS

Commands all_commands() {
  Commands all;
  for (auto* make : {
#define ROVERLAB_COMMANDS(name) &make_##name##_commands,
#include "app/commands.def"
#undef ROVERLAB_COMMANDS
       }) {
    for (auto& c : make()) all.push_back(std::move(c));
  }
  return all;
}

namespace {

// Commands that only group others: `roverlab estimate` alone is a usage error.
const std::map<std::string, std::string>& command_groups() {
  static const std::map<std::string, std::string> groups = {
      {"estimate", "Run an estimator over a log"},
      {"discrepancy", "Where a model disagrees with measured data, why, and what an extended model gains"},
      {"scenario", "Write a simulated log with truth streams"},
      {"soil", "Soil parameters from lab tests (plate sinkage)"},
  };
  return groups;
}

struct Parser {
  CLI::App cli{"RoverLab: analysis and visualisation of planetary-rover field-test logs"};
  std::map<std::string, CLI::App*> nodes;  // by path

  CLI::App* parent_of(const std::string& path) {
    const auto space = path.rfind(' ');
    if (space == std::string::npos) return &cli;
    const std::string parent = path.substr(0, space);
    if (const auto it = nodes.find(parent); it != nodes.end()) return it->second;
    const auto group = command_groups().find(parent);
    if (group == command_groups().end()) throw std::logic_error("command " + path + " has no parent " + parent);
    CLI::App* node = parent_of(parent)->add_subcommand(parent.substr(parent.rfind(' ') + 1), group->second);
    node->require_subcommand(1);
    nodes[parent] = node;
    return node;
  }

  void add(Command& c) {
    const std::string path = c.path();
    CLI::App* parent = parent_of(path);
    CLI::App* node = parent->add_subcommand(path.substr(path.rfind(' ') + 1), c.help());
    c.declare(*node);
    nodes[path] = node;
    // A command with options of its own may also have subcommands
    // (`terramechanics surface`): at most one of them.
    if (parent != &cli && command_groups().count(path.substr(0, path.rfind(' '))) == 0) {
      parent->require_subcommand(0, 1);
    }
  }
};

int parse_and_run(int argc, char** argv) {
  Parser p;
  p.cli.require_subcommand(1);
  p.cli.set_version_flag("--version", ROVERLAB_VERSION);
  p.cli.failure_message([](const CLI::App*, const CLI::Error& e) {
    return "roverlab: " + std::string(e.what()) + "\nRun with --help for more information.\n";
  });
  bool verbose = false;
  p.cli.add_flag("--verbose", verbose, "Also show the messages of the libraries RoverLab uses (Ceres, VTK)");
  bool progress = false;
  p.cli.add_flag("--progress", progress,
                 "Progress on stderr also when it is not a terminal: a line every 5 s on long work (studies, "
                 "simulations) and one when it is done");
  RosInputOptions& ros = ros_input_options();
  p.cli
      .add_option("--ros-time", ros.time,
                  "ROS bags and MCAP files: a message's time is its record time (record, the default) or its "
                  "header.stamp where its type has a std_msgs/Header (header)")
      ->check(CLI::IsMember({"record", "header"}));
  p.cli
      .add_option("--ros-max-array", ros.max_array,
                  "ROS bags and MCAP files: arrays of up to N elements become channels, longer ones are "
                  "skipped (default 64)")
      ->check(CLI::Range(std::size_t{0}, std::size_t{1} << 20));
  std::optional<std::size_t> threads;
  p.cli
      .add_option("--threads", threads,
                  "Threads a study's independent parts run on (default: the machine's, or ROVERLAB_THREADS); "
                  "the results are the same on any number")
      ->check(CLI::Range(std::size_t{1}, std::size_t{4096}));
  p.cli.fallthrough();  // --verbose (and --ros-*, --threads) also after the subcommand's name
  Commands commands = all_commands();
  for (auto& c : commands) p.add(*c);
  try {
    p.cli.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return p.cli.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return p.cli.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return p.cli.exit(e);
  } catch (const CLI::ParseError& e) {
    p.cli.exit(e);
    return kUsageError;
  }
  route_library_messages(verbose);
  set_progress_lines(progress);
  views::route_vtk_messages(verbose);
  try {
    set_thread_count(threads ? *threads : default_thread_count());
  } catch (const std::invalid_argument& e) {
    throw UsageError(e.what());
  }
  // The deepest command given runs (`terramechanics surface`, not `terramechanics`).
  Command* chosen = nullptr;
  std::size_t depth = 0;
  for (auto& c : commands) {
    const std::string path = c->path();
    const std::size_t d = static_cast<std::size_t>(std::count(path.begin(), path.end(), ' ')) + 1;
    if (p.nodes.at(path)->parsed() && d > depth) {
      chosen = c.get();
      depth = d;
    }
  }
  return chosen != nullptr ? chosen->run() : kUsageError;
}

}  // namespace

namespace {
std::vector<std::string>& arguments() {
  static std::vector<std::string> args;
  return args;
}
}  // namespace

const std::vector<std::string>& command_arguments() { return arguments(); }

int run_command_line(int argc, char** argv) {
  arguments().assign(argv, argv + argc);
  try {
    return parse_and_run(argc, argv);
  } catch (const UsageError& e) {
    std::cerr << "roverlab: " << printable(e.what(), 4000) << "\n";
    return kUsageError;
  } catch (const InputError& e) {
    std::cerr << "roverlab: " << printable(e.what(), 4000) << "\n";
    return kBadInput;
  } catch (const DataError& e) {
    std::cerr << "roverlab: " << printable(e.what(), 4000) << "\n";
    return kBadInput;
  } catch (const views::EnvironmentError& e) {
    std::cerr << "roverlab: " << printable(e.what(), 4000) << "\n";
    return kInternalFailure;
  } catch (const std::exception& e) {
    std::cerr << "roverlab: internal error: " << printable(e.what(), 4000) << "\n";
    return kInternalFailure;
  } catch (...) {
    std::cerr << "roverlab: internal error\n";
    return kInternalFailure;
  }
}

}  // namespace roverlab::app
