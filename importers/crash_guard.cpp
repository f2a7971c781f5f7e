#include "importers/crash_guard.h"

#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <cstring>

#include "core/common/error.h"

namespace roverlab::io {

void survive_crash(const std::string& path, const std::function<void()>& trial) {
  const pid_t child = fork();
  if (child < 0) return;  // no child to spare: read without the guard
  if (child == 0) {
    // The child only reads: no exit handlers, no stdio flush, no destructors
    // of the parent's objects.
    try {
      trial();
    } catch (...) {
    }
    _exit(0);
  }
  int status = 0;
  while (waitpid(child, &status, 0) < 0) {
    if (errno != EINTR) return;
  }
  if (WIFSIGNALED(status)) {
    const int sig = WTERMSIG(status);
    throw InputError(path, std::string("corrupt HDF5 file: the HDF5 library crashed reading it (") + strsignal(sig) +
                               "); the file is damaged");
  }
}

}  // namespace roverlab::io
