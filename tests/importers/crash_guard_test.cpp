// importers/crash_guard.h: the child-process trial read of an untrusted HDF5
// file (issue 17). A child that dies or ends itself is the file's fault, in
// one InputError naming the file; a child that returns is not.
#include <gtest/gtest.h>

#include <unistd.h>

#include <functional>
#include <stdexcept>
#include <string>

#include "core/common/error.h"
#include "importers/crash_guard.h"

using namespace roverlab;

namespace {

std::string guard_error(const std::function<void()>& trial) {
  try {
    io::survive_crash("/data/log.h5", trial);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(CrashGuard, AChildThatReturnsOrThrowsIsNotTheFilesFault) {
  EXPECT_EQ(guard_error([] {}), "");
  // The real read in the parent gives the clean error of a throw.
  EXPECT_EQ(guard_error([] { throw std::runtime_error("bad dataset"); }), "");
}

// A child killed by a signal: Robustness.OneCorruptedByteInAnHdf5LogIsABadInputNotACrash
// (a raised SIGSEGV here would be an ASan report under scripts/sanitize).

// Found by fuzzing (hdf5_guard, 26 Nov 2026): the child ended by an
// out-of-memory handler's exit, not a signal, and the parent then read the
// file itself and met the same fate.
TEST(CrashGuard, AChildThatEndsItselfIsACorruptFile) {
  const std::string e = guard_error([] { _exit(71); });
  EXPECT_NE(e.find("/data/log.h5"), std::string::npos) << e;
  EXPECT_NE(e.find("corrupt HDF5 file: reading it ended the process (exit status 71)"), std::string::npos) << e;
}
