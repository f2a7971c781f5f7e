// Atomic writes: an interrupted write leaves neither a partial target nor its
// temporary file (shared/robustness/findings.md F30).
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <csignal>
#include <fstream>

#include "importers/atomic_file.h"
#include "test_support.h"

namespace roverlab {
namespace {

TEST(AtomicFile, AWriteInterruptedBySigtermLeavesNothingBehind) {
  for (const int sig : {SIGTERM, SIGINT}) {
    test::TempDir dir;
    const std::string target = dir.file("out.h5");
    test::write_text(target, "previous");
    const pid_t child = fork();
    ASSERT_GE(child, 0);
    if (child == 0) {
      std::signal(sig, SIG_DFL);
      io::write_atomically(target, [&](const std::string& temporary) {
        std::ofstream(temporary) << "half of the new content";
        ::raise(sig);  // Ctrl-C or a CI cancel in the middle of the write
      });
      _exit(0);
    }
    int status = 0;
    ASSERT_EQ(waitpid(child, &status, 0), child);
    ASSERT_TRUE(WIFSIGNALED(status));
    EXPECT_EQ(WTERMSIG(status), sig);
    EXPECT_EQ(test::read_text(target), "previous");
    EXPECT_EQ(test::files_in(dir.path()), 1u) << "a temporary file was left behind";
  }
}

TEST(AtomicFile, ACompletedWriteReplacesTheTarget) {
  test::TempDir dir;
  const std::string target = dir.file("a.txt");
  io::write_text_atomically(target, "one");
  io::write_text_atomically(target, "two");
  EXPECT_EQ(test::read_text(target), "two");
  EXPECT_EQ(test::files_in(dir.path()), 1u);
}

}  // namespace
}  // namespace roverlab
