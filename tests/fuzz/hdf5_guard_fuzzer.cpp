// libFuzzer target: load_log (importers/log_file.h) on HDF5 input, the path a
// user's file takes: signature check, the trial read in a forked child
// (importers/crash_guard.h), then the read here. A crash inside libhdf5 must
// end as an InputError ("corrupt HDF5 file: ..."), never here. Slow (one fork
// per input): run briefly.
#include <cstddef>
#include <cstdint>

#include "fuzz_support.h"
#include "importers/log_file.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const roverlab::fuzz::InputFile file("log.h5");
  const std::string& path = file.write(data, size);
  roverlab::fuzz::expect_success_or_input_error([&] { (void)roverlab::io::load_log(path); });
  return 0;
}
