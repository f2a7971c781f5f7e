#include "app/resources.h"

#include <cstdlib>
#include <system_error>

namespace roverlab::app {

namespace fs = std::filesystem;

std::vector<fs::path> resource_folders() {
  std::vector<fs::path> candidates;
  if (const char* env = std::getenv("ROVERLAB_RESOURCES"); env != nullptr && *env != '\0') {
    candidates.emplace_back(env);
  }
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (!ec) candidates.push_back(exe.parent_path().parent_path() / "share" / "roverlab" / "resources");
  candidates.emplace_back(ROVERLAB_SOURCE_RESOURCES);
  std::vector<fs::path> folders;
  for (const auto& c : candidates) {
    if (fs::is_directory(c, ec)) folders.push_back(c);
  }
  return folders;
}

std::vector<fs::path> resource_subfolders(const std::string& sub) {
  std::vector<fs::path> out;
  for (const auto& folder : resource_folders()) out.push_back(folder / sub);
  return out;
}

}  // namespace roverlab::app
