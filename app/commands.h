#pragma once
// The roverlab subcommands. Each returns the process exit code; errors are
// thrown (InputError -> 3, anything else -> 4) and reported by main.

#include <optional>
#include <string>

namespace roverlab::app {

enum ExitCode : int { kSuccess = 0, kUsageError = 2, kBadInput = 3, kInternalFailure = 4 };

struct InfoOptions {
  std::string file;
  std::optional<std::string> mapping;
  bool json = false;
};
int run_info(const InfoOptions& options);

struct ConvertOptions {
  std::string input;
  std::string output;
  std::optional<std::string> mapping;
};
int run_convert(const ConvertOptions& options);

int run_list_mappings();

}  // namespace roverlab::app
