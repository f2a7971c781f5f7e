#pragma once
// What every roverlab command shares: exit codes, the usage error, `--effect`
// options. The commands themselves are registered in app/commands.def (see
// app/command.h); each returns the process exit code and throws on errors
// (UsageError -> 2, InputError / DataError -> 3, anything else -> 4).

#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

namespace roverlab::app {

enum ExitCode : int { kSuccess = 0, kUsageError = 2, kBadInput = 3, kInternalFailure = 4 };

// Options that parse but make no sense together (exit code 2).
class UsageError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Applies `--effect NAME=VALUE` options through `set` (which throws
// DataError for an unknown name or value); malformed options and rejected
// effects are UsageErrors.
void apply_effect_options(const std::vector<std::string>& options,
                          const std::function<void(const std::string& name, double value)>& set);

}  // namespace roverlab::app
