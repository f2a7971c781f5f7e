// libFuzzer target: the CSV log reader (importers/csv_log.h).
#include <cstddef>
#include <cstdint>

#include "fuzz_support.h"
#include "importers/csv_log.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const roverlab::fuzz::InputFile file("log.csv");
  const std::string& path = file.write(data, size);
  roverlab::fuzz::expect_success_or_input_error([&] { (void)roverlab::io::read_csv_log(path); });
  return 0;
}
