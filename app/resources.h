#pragma once
// Where the executable finds resources/ (mappings, rovers, soils, ...).

#include <filesystem>
#include <string>
#include <vector>

namespace roverlab::app {

// In order: $ROVERLAB_RESOURCES, <executable>/../share/roverlab/resources,
// the source tree's resources/ (when run from a build tree). Only folders
// that exist are returned.
std::vector<std::filesystem::path> resource_folders();

// resource_folders() each joined with `sub` (e.g. "mappings").
std::vector<std::filesystem::path> resource_subfolders(const std::string& sub);

}  // namespace roverlab::app
