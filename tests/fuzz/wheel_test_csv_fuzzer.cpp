// libFuzzer target: the single-wheel test-bed CSV reader (importers/wheel_test_csv.h).
#include <cstddef>
#include <cstdint>

#include "fuzz_support.h"
#include "importers/wheel_test_csv.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const roverlab::fuzz::InputFile file("points.csv");
  const std::string& path = file.write(data, size);
  roverlab::fuzz::expect_success_or_input_error([&] { (void)roverlab::io::read_wheel_test_csv(path); });
  return 0;
}
