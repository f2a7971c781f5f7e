#pragma once
// Editing a RoverLab HDF5 log in place for the robustness tests: what a
// damaged or hand-edited file holds.

#include <gtest/gtest.h>
#include <hdf5.h>

#include <string>

namespace roverlab::test {

// Sets the string attribute `key` of /metadata to `value` (replacing it).
inline void set_metadata(hid_t file, const std::string& key, const std::string& value) {
  const hid_t g = H5Gopen2(file, "/metadata", H5P_DEFAULT);
  ASSERT_GE(g, 0);
  if (H5Aexists(g, key.c_str()) > 0) H5Adelete(g, key.c_str());
  const hid_t type = H5Tcopy(H5T_C_S1);
  H5Tset_size(type, value.size());
  const hid_t space = H5Screate(H5S_SCALAR);
  const hid_t a = H5Acreate2(g, key.c_str(), type, space, H5P_DEFAULT, H5P_DEFAULT);
  ASSERT_GE(H5Awrite(a, type, value.data()), 0);
  H5Aclose(a);
  H5Sclose(space);
  H5Tclose(type);
  H5Gclose(g);
}

}  // namespace roverlab::test
