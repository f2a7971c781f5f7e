// libFuzzer target: the MATLAB v7.3 importer (importers/matlab_importer.h)
// with the WVU Pathfinder mapping (resources/mappings/wvu_pathfinder.json),
// in this process, without the child-process guard (see hdf5_log_fuzzer.cpp).
#include <cstddef>
#include <cstdint>

#include "fuzz_support.h"
#include "importers/mapping.h"
#include "importers/matlab_importer.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const roverlab::io::Mapping mapping =
      roverlab::io::load_mapping(ROVERLAB_RESOURCES_DIR "/mappings/wvu_pathfinder.json");
  static const roverlab::fuzz::InputFile file("log.mat");
  const std::string& path = file.write(data, size);
  roverlab::fuzz::expect_success_or_input_error([&] { (void)roverlab::io::read_mapped_hdf5(path, mapping); });
  return 0;
}
