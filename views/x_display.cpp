#include "views/x_display.h"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <cstring>
#include <filesystem>

namespace roverlab::views {

namespace {

pid_t xvfb_pid = -1;

void stop_xvfb() {
  if (xvfb_pid > 0) {
    kill(xvfb_pid, SIGTERM);
    waitpid(xvfb_pid, nullptr, 0);
    xvfb_pid = -1;
  }
}

std::string find_in_path(const std::string& name) {
  const char* path = std::getenv("PATH");
  std::string p = path ? path : "/usr/bin:/bin";
  std::size_t a = 0;
  while (a <= p.size()) {
    std::size_t b = p.find(':', a);
    if (b == std::string::npos) b = p.size();
    const std::filesystem::path candidate = std::filesystem::path(p.substr(a, b - a)) / name;
    if (access(candidate.c_str(), X_OK) == 0) return candidate.string();
    a = b + 1;
  }
  return {};
}

}  // namespace

int private_xvfb_pid() { return xvfb_pid; }

std::string ensure_display() {
  const char* d = std::getenv("DISPLAY");
  if (d != nullptr && *d != '\0') return d;
  const std::string xvfb = find_in_path("Xvfb");
  const char* how =
      "no X display for rendering: set DISPLAY, install Xvfb (apt-get install xvfb) "
      "or run under `xvfb-run -a`";
  if (xvfb.empty()) throw EnvironmentError(how);
  int fds[2];
  if (pipe(fds) != 0) throw EnvironmentError(how);
  const pid_t parent = getpid();
  const pid_t pid = fork();
  if (pid < 0) throw EnvironmentError(how);
  if (pid == 0) {
    // Xvfb ends with its parent, however the parent ends (SIGKILL, a crash):
    // no orphaned X server left on a CI machine.
    prctl(PR_SET_PDEATHSIG, SIGTERM);
    if (getppid() != parent) _exit(127);
    close(fds[0]);
    const int devnull = open("/dev/null", O_RDWR);
    if (devnull >= 0) {
      dup2(devnull, 0);
      dup2(devnull, 1);
      dup2(devnull, 2);
    }
    const std::string fd = std::to_string(fds[1]);
    execl(xvfb.c_str(), "Xvfb", "-displayfd", fd.c_str(), "-screen", "0", "1920x1200x24", "-nolisten", "tcp",
          "-noreset", static_cast<char*>(nullptr));
    _exit(127);
  }
  close(fds[1]);
  // Xvfb writes its display number and a newline once it accepts clients.
  std::string number;
  pollfd pfd{fds[0], POLLIN, 0};
  char c = 0;
  while (poll(&pfd, 1, 10000) > 0 && read(fds[0], &c, 1) == 1 && c != '\n') number += c;
  close(fds[0]);
  if (number.empty()) {
    kill(pid, SIGTERM);
    waitpid(pid, nullptr, 0);
    throw EnvironmentError(std::string("could not start Xvfb (") + xvfb + "); " + how);
  }
  xvfb_pid = pid;
  std::atexit(stop_xvfb);
  std::string display = ":" + number;
  setenv("DISPLAY", display.c_str(), 1);
  return display;
}

}  // namespace roverlab::views
