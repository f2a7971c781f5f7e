// libFuzzer target: the MCAP reader (importers/mcap_file.h) and, through it,
// the ROS message-definition parser and the ROS 1, CDR and JSON decoders. All
// of it is RoverLab's own code: no crash guard, nothing may escape but an
// InputError.
#include <cstddef>
#include <cstdint>

#include "fuzz_support.h"
#include "importers/mcap_file.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const roverlab::fuzz::InputFile file("log.mcap");
  const std::string& path = file.write(data, size);
  roverlab::fuzz::expect_success_or_input_error([&] { (void)roverlab::io::read_mcap(path, {}); });
  return 0;
}
