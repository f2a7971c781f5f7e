// libFuzzer target: the JSON resource readers (importers/json_resource.h):
// every input is read as a rover, a soil, a scenario, a mapping and a
// campaign file (issue 34 item 6).
#include <cstddef>
#include <cstdint>

#include "fuzz_support.h"
#include "importers/campaign_file.h"
#include "importers/mapping.h"
#include "importers/rover_file.h"
#include "importers/scenario_file.h"
#include "importers/soil_file.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace roverlab;
  static const fuzz::InputFile file("resource.json");
  const std::string& path = file.write(data, size);
  fuzz::expect_success_or_input_error([&] { (void)io::load_rover(path); });
  fuzz::expect_success_or_input_error([&] { (void)io::load_soil(path); });
  fuzz::expect_success_or_input_error([&] { (void)io::load_scenario(path); });
  fuzz::expect_success_or_input_error([&] { (void)io::load_mapping(path); });
  fuzz::expect_success_or_input_error([&] { (void)io::read_campaign_file(path); });
  return 0;
}
