#include "importers/crash_guard.h"

#include <fcntl.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
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

namespace {

// The child's CPU time in seconds, from its resource usage.
double cpu_seconds_of(const rusage& u) {
  return static_cast<double>(u.ru_utime.tv_sec + u.ru_stime.tv_sec) +
         1e-6 * static_cast<double>(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

}  // namespace

void survive_crash(const std::string& path, const std::function<void()>& trial, const std::string& format,
                   const std::string& library, int cpu_seconds) {
  // A library that loops on a damaged file must not hang RoverLab: the child
  // gets 30 s of CPU plus 1 s per MB. CPU time, not wall-clock time: on a
  // loaded machine a valid file's read waits for a core, it does not loop.
  // What a read costs grows with the file's objects more than its bytes: a
  // 312 MB log reads in 0.5 s, the 78 MB log of 65,535 one-sample streams
  // (probe 3's chan65535.mcap converted) in 20-26 s of CPU (libhdf5's
  // metadata over 65,535 groups), where 20 s of wall-clock time refused it.
  std::error_code ec;
  const auto bytes = std::filesystem::file_size(path, ec);
  const rlim_t cpu =
      cpu_seconds > 0 ? static_cast<rlim_t>(cpu_seconds) : static_cast<rlim_t>(30 + (ec ? 0 : bytes / 1'000'000));
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
    const rlimit limit{cpu, cpu + 2};  // SIGXCPU at the soft limit, SIGKILL at the hard one
    setrlimit(RLIMIT_CPU, &limit);
    try {
      trial();
    } catch (...) {
    }
    _exit(0);  // no exit handlers, no destructors of the parent's objects
  }
  // A child that neither ends nor uses CPU (blocked on something) is stopped
  // after a wall-clock limit far above any load: 10 x its CPU time, at least 5 minutes.
  const rlim_t backstop_seconds = std::max<rlim_t>(300, 10 * cpu);
  const auto backstop = std::chrono::steady_clock::now() + std::chrono::seconds(backstop_seconds);
  int status = 0;
  rusage usage{};
  const std::string corrupt = "corrupt " + format + ": ";
  for (;;) {
    const pid_t done = wait4(child, &status, WNOHANG, &usage);
    if (done == child) break;
    if (done < 0 && errno != EINTR) return;
    if (std::chrono::steady_clock::now() > backstop) {
      kill(child, SIGKILL);
      while (waitpid(child, &status, 0) < 0 && errno == EINTR) {
      }
      throw InputError(path, corrupt + "reading it did not end in " + std::to_string(backstop_seconds) + " s (the " +
                                 library + " is stuck on it); the file is damaged");
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  // SIGXCPU: the soft limit; SIGKILL after the CPU the hard limit allows.
  if (WIFSIGNALED(status) && (WTERMSIG(status) == SIGXCPU ||
                              (WTERMSIG(status) == SIGKILL && cpu_seconds_of(usage) >= static_cast<double>(cpu)))) {
    throw InputError(path, corrupt + "reading it used more than " + std::to_string(cpu) + " s of CPU (the " + library +
                               " loops on it); the file is damaged");
  }
  if (WIFSIGNALED(status)) {
    throw InputError(path, corrupt + "the " + library + " crashed reading it (" + strsignal(WTERMSIG(status)) +
                               "); the file is damaged");
  }
  // The child ends only by _exit(0) above: any other status is a library (or
  // an allocator's out-of-memory handler) ending the process from inside.
  if (WIFEXITED(status) && WEXITSTATUS(status) != 0) {
    throw InputError(path, corrupt + "reading it ended the process (exit status " +
                               std::to_string(WEXITSTATUS(status)) + "); the file is damaged");
  }
}

}  // namespace roverlab::io
