#include "importers/crash_guard.h"

#include <fcntl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <string>
#include <thread>

#include "core/common/error.h"

namespace roverlab::io {

bool has_hdf5_signature(const std::string& path) {
  static const char kSignature[8] = {'\x89', 'H', 'D', 'F', '\r', '\n', '\x1a', '\n'};
  std::FILE* in = std::fopen(path.c_str(), "rb");
  if (in == nullptr) return false;
  bool found = false;
  // The superblock is at 0, 512, 1024, 2048, ... (a MATLAB v7.3 file has a
  // 512-byte text header first).
  for (long at = 0; at <= (1L << 30) && !found; at = at == 0 ? 512 : 2 * at) {
    char head[8];
    if (std::fseek(in, at, SEEK_SET) != 0 || std::fread(head, 1, 8, in) != 8) break;
    found = std::memcmp(head, kSignature, 8) == 0;
  }
  std::fclose(in);
  return found;
}

void survive_crash(const std::string& path, const std::function<void()>& trial, const std::string& format,
                   const std::string& library) {
  std::fflush(nullptr);  // nothing buffered is written twice
  const pid_t child = fork();
  if (child < 0) return;
  if (child == 0) {
    // The library's or the C runtime's last words ("double free or
    // corruption") are not RoverLab's one line: the child says nothing.
    const int quiet = ::open("/dev/null", O_WRONLY);
    if (quiet >= 0) {
      ::dup2(quiet, STDOUT_FILENO);
      ::dup2(quiet, STDERR_FILENO);
    }
    try {
      trial();
    } catch (...) {
    }
    _exit(0);  // no exit handlers, no destructors of the parent's objects
  }
  // A library that loops on a damaged file must not hang RoverLab: the child
  // gets 20 s plus 1 s per 10 MB (a 312 MB log reads in 0.5 s).
  std::error_code ec;
  const auto bytes = std::filesystem::file_size(path, ec);
  const auto limit = std::chrono::steady_clock::now() + std::chrono::seconds(20) +
                     std::chrono::milliseconds(ec ? 0 : static_cast<long long>(bytes / 10'000));
  int status = 0;
  for (;;) {
    const pid_t done = waitpid(child, &status, WNOHANG);
    if (done == child) break;
    if (done < 0 && errno != EINTR) return;
    if (std::chrono::steady_clock::now() > limit) {
      kill(child, SIGKILL);
      while (waitpid(child, &status, 0) < 0 && errno == EINTR) {
      }
      throw InputError(path, "corrupt " + format + ": reading it did not finish in time (the " + library +
                                 " loops on it); the file is damaged");
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  if (WIFSIGNALED(status)) {
    throw InputError(path, "corrupt " + format + ": the " + library + " crashed reading it (" +
                               strsignal(WTERMSIG(status)) + "); the file is damaged");
  }
  // The child ends only by _exit(0) above: any other status is a library (or
  // an allocator's out-of-memory handler) ending the process from inside.
  if (WIFEXITED(status) && WEXITSTATUS(status) != 0) {
    throw InputError(path, "corrupt " + format + ": reading it ended the process (exit status " +
                               std::to_string(WEXITSTATUS(status)) + "); the file is damaged");
  }
}

}  // namespace roverlab::io
