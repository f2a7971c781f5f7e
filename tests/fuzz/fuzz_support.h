#pragma once
// Shared by the libFuzzer targets: the readers take file names, so each input
// is written to one file in a private folder (on /dev/shm when there is one),
// and the one failure a reader may report for bad bytes is an InputError
// naming the file (the command line's exit 3). Anything else escaping a
// reader (a DataError, std::bad_alloc, a nlohmann::json exception, ...) is a
// finding: the program would call it an internal failure (exit 4).

#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <fstream>
#include <string>
#include <typeinfo>

#include "core/common/error.h"

namespace roverlab::fuzz {

class InputFile {
 public:
  explicit InputFile(const std::string& name) {
    namespace fs = std::filesystem;
    std::error_code ec;
    const fs::path base = fs::is_directory("/dev/shm", ec) ? fs::path("/dev/shm") : fs::temp_directory_path();
    std::string pattern = (base / "roverlab-fuzz-XXXXXX").string();
    if (mkdtemp(pattern.data()) == nullptr) {
      std::perror("fuzz: mkdtemp");
      std::abort();
    }
    folder_ = pattern;
    path_ = folder_ + "/" + name;
  }
  ~InputFile() {
    std::error_code ec;
    std::filesystem::remove_all(folder_, ec);
  }
  InputFile(const InputFile&) = delete;
  InputFile& operator=(const InputFile&) = delete;

  // Replaces the file's content with the input; returns its path.
  const std::string& write(const std::uint8_t* data, std::size_t size) const {
    std::ofstream out(path_, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
    out.close();
    if (!out) {
      std::fprintf(stderr, "fuzz: cannot write %s\n", path_.c_str());
      std::abort();
    }
    return path_;
  }

 private:
  std::string folder_;
  std::string path_;
};

// Runs one read; returns normally on success or an InputError, aborts (a
// finding, with the exception's type and text) on anything else.
template <class Read>
void expect_success_or_input_error(Read read) {
  try {
    read();
  } catch (const InputError&) {
  } catch (const std::exception& e) {
    std::fprintf(stderr, "fuzz: %s escaped the reader: %s\n", typeid(e).name(), e.what());
    std::abort();
  }
}

}  // namespace roverlab::fuzz
