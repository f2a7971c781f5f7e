// libFuzzer target: load_log (importers/log_file.h) on ROS 1 bags, the path a
// user's file takes: the rosbag library's trial read in a forked child
// (importers/crash_guard.h; the library crashes on some damaged bags), then
// the read and the generic decoding here. Slow (one fork per input): run
// briefly.
#include <cstddef>
#include <cstdint>

#include "fuzz_support.h"
#include "importers/log_file.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const roverlab::fuzz::InputFile file("log.bag");
  const std::string& path = file.write(data, size);
  roverlab::fuzz::expect_success_or_input_error([&] { (void)roverlab::io::load_log(path); });
  return 0;
}
