// Writes the HDF5 and MATLAB seeds of tests/fuzz/corpus/ (a few kB each, so
// that the fuzzer mutates small files) from the bundled WVU Pathfinder log
// tests/data/test17run.mat (MIT licence, tests/data/LICENSE):
//   corpus/hdf5_log/small.h5, corpus/hdf5_guard/small.h5: its first 0.5 s as
//     a RoverLab HDF5 log;
//   corpus/matlab_mapping/small.mat: the variables of the wvu_pathfinder
//     mapping, each cut to its first 20 samples, behind the same MATLAB header.
// Usage: fuzz_make_seeds CORPUS_FOLDER
#include <hdf5.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <set>
#include <string>
#include <vector>

#include "importers/hdf5_log.h"
#include "importers/mapping.h"
#include "importers/matlab_importer.h"

namespace {

using roverlab::io::Mapping;

// One variable of `in`, its sample axis (the longer one) cut to `keep`, as doubles in `out`.
void copy_cut(hid_t in, hid_t out, const std::string& name, hsize_t keep) {
  const hid_t ds = H5Dopen2(in, name.c_str(), H5P_DEFAULT);
  const hid_t space = H5Dget_space(ds);
  std::vector<hsize_t> dims(static_cast<std::size_t>(H5Sget_simple_extent_ndims(space)));
  H5Sget_simple_extent_dims(space, dims.data(), nullptr);
  std::vector<double> values(static_cast<std::size_t>(H5Sget_simple_extent_npoints(space)));
  H5Dread(ds, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data());
  H5Sclose(space);
  H5Dclose(ds);

  const hsize_t rows = dims.empty() ? 1 : dims[0];
  const hsize_t cols = dims.size() < 2 ? 1 : dims[1];
  std::vector<double> cut;
  std::vector<hsize_t> cut_dims = dims;
  if (cols >= rows) {  // [rows, cols]: keep the first `keep` columns of each row
    const hsize_t kept = std::min(cols, keep);
    for (hsize_t r = 0; r < rows; ++r) {
      for (hsize_t c = 0; c < kept; ++c) cut.push_back(values[r * cols + c]);
    }
    if (dims.size() >= 2) cut_dims[1] = kept;
  } else {
    const hsize_t kept = std::min(rows, keep);
    cut.assign(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(kept * cols));
    cut_dims[0] = kept;
  }
  const hid_t out_space = H5Screate_simple(static_cast<int>(cut_dims.size()), cut_dims.data(), nullptr);
  const hid_t out_ds = H5Dcreate2(out, name.c_str(), H5T_IEEE_F64LE, out_space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  H5Dwrite(out_ds, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, cut.data());
  H5Dclose(out_ds);
  H5Sclose(out_space);
}

void write_small_mat(const std::string& from, const Mapping& mapping, const std::string& to, hsize_t keep) {
  std::set<std::string> variables;
  for (const auto& stream : mapping.streams) {
    variables.insert(stream.time_variable);
    for (const auto& channel : stream.channels) variables.insert(channel.variable);
  }
  const hid_t in = H5Fopen(from.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  const hid_t fcpl = H5Pcreate(H5P_FILE_CREATE);
  H5Pset_userblock(fcpl, 512);
  const hid_t out = H5Fcreate(to.c_str(), H5F_ACC_TRUNC, fcpl, H5P_DEFAULT);
  H5Pclose(fcpl);
  for (const auto& name : variables) copy_cut(in, out, name, keep);
  H5Fclose(out);
  H5Fclose(in);

  // The MATLAB header (128 bytes of text) in the user block.
  char header[128] = {};
  std::ifstream(from, std::ios::binary).read(header, sizeof header);
  std::fstream file(to, std::ios::binary | std::ios::in | std::ios::out);
  file.write(header, sizeof header);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: fuzz_make_seeds CORPUS_FOLDER\n");
    return 2;
  }
  namespace io = roverlab::io;
  const std::string corpus = argv[1];
  const std::string mat = ROVERLAB_TEST_DATA "/test17run.mat";
  const Mapping mapping = io::load_mapping(ROVERLAB_RESOURCES_DIR "/mappings/wvu_pathfinder.json");
  for (const char* folder : {"hdf5_log", "hdf5_guard", "matlab_mapping"}) {
    std::filesystem::create_directories(corpus + "/" + folder);
  }
  const roverlab::log::Log small = io::read_mapped_hdf5(mat, mapping).slice(0.0, 0.5);
  io::write_hdf5_log(small, corpus + "/hdf5_log/small.h5");
  io::write_hdf5_log(small, corpus + "/hdf5_guard/small.h5");
  write_small_mat(mat, mapping, corpus + "/matlab_mapping/small.mat", 20);
  return 0;
}
