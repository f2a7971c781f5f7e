// The private Xvfb never outlives RoverLab: not when it exits, not when it is
// killed (shared/robustness/findings.md F39).
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <fstream>
#include <string>
#include <thread>

#include "views/x_display.h"

namespace roverlab {
namespace {

// Running: exists and is not a zombie waiting for its new parent to reap it.
bool alive(pid_t pid) {
  if (kill(pid, 0) != 0) return false;
  std::ifstream stat("/proc/" + std::to_string(pid) + "/stat");
  std::string line;
  std::getline(stat, line);
  const auto close = line.rfind(')');
  return close == std::string::npos || close + 2 >= line.size() || line[close + 2] != 'Z';
}

bool gone_within(pid_t pid, std::chrono::milliseconds limit) {
  const auto end = std::chrono::steady_clock::now() + limit;
  while (std::chrono::steady_clock::now() < end) {
    if (!alive(pid)) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return !alive(pid);
}

TEST(PrivateXvfb, StopsWhenRoverLabIsKilled) {
  int fds[2];
  ASSERT_EQ(pipe(fds), 0);
  const pid_t child = fork();
  ASSERT_GE(child, 0);
  if (child == 0) {  // a RoverLab render that gets SIGKILLed mid-way
    unsetenv("DISPLAY");
    views::ensure_display();
    const int xvfb = views::private_xvfb_pid();
    (void)!write(fds[1], &xvfb, sizeof xvfb);
    pause();
    _exit(0);
  }
  close(fds[1]);
  int xvfb = -1;
  ASSERT_EQ(read(fds[0], &xvfb, sizeof xvfb), static_cast<ssize_t>(sizeof xvfb));
  close(fds[0]);
  ASSERT_GT(xvfb, 0);
  EXPECT_TRUE(alive(xvfb));
  kill(child, SIGKILL);
  waitpid(child, nullptr, 0);
  // Xvfb is the killed process's child: once reparented, nobody reaps it here,
  // but it must stop running.
  EXPECT_TRUE(gone_within(xvfb, std::chrono::milliseconds(5000))) << "Xvfb " << xvfb << " outlived its parent";
}

}  // namespace
}  // namespace roverlab
