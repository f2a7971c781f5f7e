#include "importers/atomic_file.h"

#include <unistd.h>

#include <atomic>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <system_error>

#include "core/common/error.h"

namespace roverlab::io {

namespace fs = std::filesystem;

void write_atomically(const std::string& path,
                      const std::function<void(const std::string& temporary_path)>& write) {
  static std::atomic<unsigned> counter{0};
  const fs::path target(path);
  const fs::path folder = target.has_parent_path() ? target.parent_path() : fs::path(".");
  std::error_code ec;
  if (!fs::is_directory(folder, ec)) {
    throw InputError(path, "cannot write: folder '" + folder.string() + "' does not exist");
  }
  if (fs::is_directory(target, ec)) {
    throw InputError(path, "cannot write: it is a folder");
  }
  const fs::path temporary =
      folder / ("." + target.filename().string() + ".tmp-" + std::to_string(::getpid()) + "-" +
                std::to_string(counter++));
  try {
    write(temporary.string());
  } catch (...) {
    fs::remove(temporary, ec);
    throw;
  }
  fs::rename(temporary, target, ec);
  if (ec) {
    std::error_code ignored;
    fs::remove(temporary, ignored);
    throw InputError(path, "cannot write: " + ec.message());
  }
}

void write_text_atomically(const std::string& path, const std::string& text) {
  write_atomically(path, [&](const std::string& temporary) {
    std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
    if (!out) throw InputError(path, "cannot write: cannot create a temporary file");
    out << text;
    out.flush();
    if (!out) throw InputError(path, "cannot write: write failed (disk full?)");
  });
}

}  // namespace roverlab::io
