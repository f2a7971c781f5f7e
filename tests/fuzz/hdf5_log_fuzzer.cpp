// libFuzzer target: RoverLab's HDF5 log reader (importers/hdf5_log.h), in
// this process, without the child-process guard of load_log: RoverLab's own
// reading code is what is fuzzed. libhdf5 itself crashes on some damaged
// files (tests/data/robustness/); such a crash here is libhdf5's, which
// load_log contains (importers/crash_guard.h, fuzz target hdf5_guard).
#include <cstddef>
#include <cstdint>

#include "fuzz_support.h"
#include "importers/hdf5_log.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const roverlab::fuzz::InputFile file("log.h5");
  const std::string& path = file.write(data, size);
  roverlab::fuzz::expect_success_or_input_error([&] { (void)roverlab::io::read_hdf5_log(path); });
  return 0;
}
