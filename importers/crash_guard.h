#pragma once
// Running a risky read in a child process first. Debian's libhdf5 1.10 can
// crash (SIGSEGV, heap corruption) on a log with one corrupted byte; a crash
// in a forked child becomes an InputError naming the file instead of taking
// the program (or the GUI session) down.

#include <functional>
#include <string>

namespace roverlab::io {

// Runs `trial` in a forked child and waits for it. Throws InputError(path,
// ...) when the child dies by a signal; returns otherwise, whatever the trial
// threw (the caller then does the real work in this process, where the same
// input gives the same, clean error).
void survive_crash(const std::string& path, const std::function<void()>& trial);

}  // namespace roverlab::io
