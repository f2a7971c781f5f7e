#pragma once
// Loading a log named on the command line, with an optional mapping NAME or
// FILE (resolved against the resource folders).

#include <optional>
#include <string>

#include "importers/log_file.h"

namespace roverlab::app {

io::LoadedLog load_input(const std::string& file, const std::optional<std::string>& mapping);

}  // namespace roverlab::app
