#include "importers/named_file.h"

#include <set>

#include "core/common/error.h"

namespace roverlab::io {

namespace fs = std::filesystem;

std::string find_named_file(const std::string& name_or_file, const std::vector<fs::path>& folders,
                            const std::string& what) {
  std::error_code ec;
  if (fs::is_regular_file(name_or_file, ec)) return name_or_file;
  if (fs::is_directory(name_or_file, ec)) throw InputError(name_or_file, "is a folder, not a " + what + " file");
  const bool looks_like_path =
      name_or_file.find('/') != std::string::npos || fs::path(name_or_file).extension() == ".json";
  if (!looks_like_path) {
    for (const auto& folder : folders) {
      const fs::path candidate = folder / (name_or_file + ".json");
      if (fs::is_regular_file(candidate, ec)) return candidate.string();
    }
  }
  std::string known;
  for (const auto& name : list_named_files(folders)) known += (known.empty() ? "" : ", ") + name;
  throw InputError(name_or_file,
                   looks_like_path
                       ? "no such " + what + " file"
                       : "no " + what + " of that name (known: " + (known.empty() ? std::string("none") : known) + ")");
}

std::vector<std::string> list_named_files(const std::vector<fs::path>& folders) {
  std::set<std::string> names;
  std::error_code ec;
  for (const auto& folder : folders) {
    if (!fs::is_directory(folder, ec)) continue;
    for (const auto& entry : fs::directory_iterator(folder, ec)) {
      if (entry.path().extension() == ".json") names.insert(entry.path().stem().string());
    }
  }
  return {names.begin(), names.end()};
}

}  // namespace roverlab::io
