#pragma once
// Reading an untrusted HDF5 file safely. Debian's libhdf5 1.10 can crash
// (SIGSEGV, heap corruption from a crafted file) on a log with one corrupted
// byte. The read is tried first in a forked child: the child starts from this
// process's exact memory state, so it meets the same fate as this process
// would; a crash there becomes an InputError naming the file, and only a file
// the child read without crashing is then read here.

#include <functional>
#include <string>

namespace roverlab::io {

// True when the file has the HDF5 signature where HDF5 puts it, read byte by
// byte (without libhdf5, which may crash on a damaged file).
bool has_hdf5_signature(const std::string& path);

// Runs `trial` in a forked child and waits for it. Throws InputError(path,
// "corrupt HDF5 file: ...") when the child dies by a signal or exits with
// a status other than 0 (something in the read ended the process); returns
// otherwise, whatever the trial threw (the real read here then gives the same,
// clean error). Without a child to spare it returns at once.
// `format` and `library` name what the message says ("ROS bag", "rosbag
// library"). The child may use `cpu_seconds` of CPU (0: 30 s plus 1 s per
// MB of the file): more is a library looping on the file (InputError);
// a child slowed by a loaded machine is not.
void survive_crash(const std::string& path, const std::function<void()>& trial, const std::string& format = "HDF5 file",
                   const std::string& library = "HDF5 library", int cpu_seconds = 0);

}  // namespace roverlab::io
