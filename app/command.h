#pragma once
// The command seam: every `roverlab` subcommand is a Command that declares its
// own options and runs. Each cmd_*.cpp defines one factory listed in
// app/commands.def; main() builds the parser from that list and maps errors to
// exit codes. Adding a command: one new file defining `make_<name>_commands()`
// and one `ROVERLAB_COMMANDS(<name>)` line in commands.def.

#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace CLI {
class App;
}

namespace roverlab::app {

class Command {
 public:
  virtual ~Command() = default;
  // The words a user types after `roverlab`, e.g. "estimate ins-slip". A
  // command's parent ("estimate") is a group (command_groups()) or another
  // command; parents come before children.
  virtual std::string path() const = 0;
  virtual std::string help() const = 0;
  // Declares the options on `cmd`, bound to the command's own members.
  virtual void declare(CLI::App& cmd) = 0;
  // Runs once the options are parsed; returns the exit code, throws on errors
  // (UsageError -> 2, InputError / DataError -> 3, anything else -> 4).
  virtual int run() = 0;
};

using Commands = std::vector<std::unique_ptr<Command>>;

// A command whose options are a plain struct: `declare` binds the struct's
// fields to options, `run` gets the parsed struct.
template <class Options>
class OptionsCommand final : public Command {
 public:
  using Declare = std::function<void(CLI::App&, Options&)>;
  using Run = std::function<int(const Options&)>;
  OptionsCommand(std::string path, std::string help, Declare declare, Run run, Options defaults)
      : path_(std::move(path)),
        help_(std::move(help)),
        declare_(std::move(declare)),
        run_(std::move(run)),
        options_(std::move(defaults)) {}
  std::string path() const override { return path_; }
  std::string help() const override { return help_; }
  void declare(CLI::App& cmd) override { declare_(cmd, options_); }
  int run() override { return run_(options_); }

 private:
  std::string path_, help_;
  Declare declare_;
  Run run_;
  Options options_;
};

template <class Options>
std::unique_ptr<Command> make_command(std::string path, std::string help,
                                      typename OptionsCommand<Options>::Declare declare,
                                      typename OptionsCommand<Options>::Run run, Options defaults = {}) {
  return std::make_unique<OptionsCommand<Options>>(std::move(path), std::move(help), std::move(declare), std::move(run),
                                                   std::move(defaults));
}

// Every registered command, in commands.def order.
Commands all_commands();

// Parses argv against every command and runs the one given; returns the exit code.
int run_command_line(int argc, char** argv);
// The arguments run_command_line() was given (argv[0] first), for a report's provenance.
const std::vector<std::string>& command_arguments();

}  // namespace roverlab::app
