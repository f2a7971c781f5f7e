#pragma once
// Resources chosen by NAME (NAME.json in a list of folders) or by FILE path:
// mappings, soils, rovers, scenarios.

#include <filesystem>
#include <string>
#include <vector>

namespace roverlab::io {

// The file for NAME (first folder that has NAME.json) or the FILE itself.
// Throws InputError listing the known names when neither exists; `what` names
// the kind of resource in the message ("mapping", "soil").
std::string find_named_file(const std::string& name_or_file, const std::vector<std::filesystem::path>& folders,
                            const std::string& what);

// Names (stems of *.json) found in `folders`, sorted, without duplicates.
std::vector<std::string> list_named_files(const std::vector<std::filesystem::path>& folders);

}  // namespace roverlab::io
