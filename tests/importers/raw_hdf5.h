#pragma once
// Writing hand-made HDF5 files for the importer tests (foreign layouts,
// wrong units, broken time bases), with the HDF5 C API directly.

#include <hdf5.h>

#include <string>
#include <vector>

namespace roverlab::test {

class RawHdf5 {
 public:
  explicit RawHdf5(const std::string& path, hsize_t user_block = 0) {
    hid_t fcpl = H5Pcreate(H5P_FILE_CREATE);
    if (user_block > 0) H5Pset_userblock(fcpl, user_block);
    file_ = H5Fcreate(path.c_str(), H5F_ACC_TRUNC, fcpl, H5P_DEFAULT);
    H5Pclose(fcpl);
  }
  ~RawHdf5() { H5Fclose(file_); }
  hid_t id() const { return file_; }

  void group(const std::string& path) {
    hid_t lcpl = H5Pcreate(H5P_LINK_CREATE);
    H5Pset_create_intermediate_group(lcpl, 1);
    H5Gclose(H5Gcreate2(file_, path.c_str(), lcpl, H5P_DEFAULT, H5P_DEFAULT));
    H5Pclose(lcpl);
  }

  // A dataset of doubles with the given shape (row-major), intermediate
  // groups created.
  hid_t dataset(const std::string& path, const std::vector<double>& values, std::vector<hsize_t> dims = {}) {
    if (dims.empty()) dims = {values.size()};
    hid_t space = H5Screate_simple(static_cast<int>(dims.size()), dims.data(), nullptr);
    hid_t lcpl = H5Pcreate(H5P_LINK_CREATE);
    H5Pset_create_intermediate_group(lcpl, 1);
    hid_t ds = H5Dcreate2(file_, path.c_str(), H5T_IEEE_F64LE, space, lcpl, H5P_DEFAULT, H5P_DEFAULT);
    H5Dwrite(ds, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data());
    H5Pclose(lcpl);
    H5Sclose(space);
    return ds;  // caller closes (after adding attributes) with H5Dclose
  }

  // The root attributes of a RoverLab log of the given format version.
  void roverlab_header(long long version) {
    string_attribute(file_, "format", "roverlab-log");
    int_attribute(file_, "format_version", version);
  }

  // A group streams/<name> marked as a RoverLab stream.
  void roverlab_stream(const std::string& name) {
    const std::string path = "streams/" + name;
    group(path);
    hid_t g = H5Gopen2(file_, path.c_str(), H5P_DEFAULT);
    string_attribute(g, "roverlab_kind", "stream");
    H5Gclose(g);
  }

  static void string_attribute(hid_t object, const char* name, const std::string& value) {
    hid_t type = H5Tcopy(H5T_C_S1);
    H5Tset_size(type, value.size());
    hid_t space = H5Screate(H5S_SCALAR);
    hid_t attr = H5Acreate2(object, name, type, space, H5P_DEFAULT, H5P_DEFAULT);
    H5Awrite(attr, type, value.data());
    H5Aclose(attr);
    H5Sclose(space);
    H5Tclose(type);
  }

  static void int_attribute(hid_t object, const char* name, long long value) {
    hid_t space = H5Screate(H5S_SCALAR);
    hid_t attr = H5Acreate2(object, name, H5T_STD_I64LE, space, H5P_DEFAULT, H5P_DEFAULT);
    H5Awrite(attr, H5T_NATIVE_LLONG, &value);
    H5Aclose(attr);
    H5Sclose(space);
  }

 private:
  hid_t file_;
};

}  // namespace roverlab::test
