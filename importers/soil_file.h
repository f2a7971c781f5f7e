#pragma once
// Soil descriptions: resources/soils/*.json (format in docs/terramechanics.md).

#include <filesystem>
#include <string>
#include <vector>

#include "core/terramechanics/soil.h"

namespace roverlab::io {

// Throws InputError naming the file: bad JSON, missing or non-finite
// parameter, value out of its physical range.
terramechanics::Soil load_soil(const std::string& path);

// NAME (resources/soils/NAME.json) or FILE.
terramechanics::Soil find_soil(const std::string& name_or_file, const std::vector<std::filesystem::path>& folders);

}  // namespace roverlab::io
